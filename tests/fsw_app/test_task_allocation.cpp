// The tasks' cycles allocate nothing once running, publishing included:
// the estimator task processing recorded frames (ring, detector, tracker,
// HANDRAIL_ESTIMATE) and the arm task's cycle (command and approach
// mailboxes, perch sequence, ARM_STATE), and frames crossing LCM (the
// frame publisher and the LCM frame source), counted on the calling thread,
// where LCM's publish runs too. The hub uses udpm on loopback as in flight;
// where the host has no multicast route the test says so and uses memq,
// whose publish copies each message (its allocations then belong to LCM's
// in-process provider, not to us, and are reported, not asserted).
#include <lcm/lcm-cpp.hpp>

#include <cstdio>
#include <vector>

#include "../arm/fake_arm_devices.hpp"
#include "allocation_counter.hpp"
#include "cmocka_cpp.hpp"
#include "formats/pcd_io.hpp"
#include "fsw_app/arm_task.hpp"
#include "fsw_app/estimator_task.hpp"
#include "fsw_app/frame_publisher.hpp"
#include "fsw_app/lcm_depth_camera.hpp"
#include "test_data.hpp"

namespace {

std::string g_url;
bool g_udpm = false;

void choose_url() {
  // The frames test publishes 0.73 MB messages, which this socket hears too.
  g_url = "udpm://239.255.76.67:7699?ttl=0&recv_buf_size=4194304";
  lcm::LCM probe(g_url);
  g_udpm = probe.good();
  if (!g_udpm) {
    std::printf("NOTE: no multicast route here; memq:// instead\n");
    g_url = "memq://";
  }
}

void expect_none(long n, const char* what) {
  std::printf("%s: %ld allocations\n", what, n);
  if (g_udpm) {
    assert_int_equal(n, 0);
  }
}

void test_estimator_task_processes_frames_without_allocating(void**) {
  fsw_app::LcmHub hub(g_url);
  assert_true(hub.good());
  hal::MonotonicClock clock;
  fsw_app::FrameRing ring(3, 224, 171);
  fsw_app::CameraTask camera(ring, 224, 171);
  fsw_app::EstimatorTaskConfig cfg;
  cfg.detector.budget_us = 1000000;
  fsw_app::EstimatorTask task(hub, camera, ring, cfg, clock);
  std::vector<formats::PcdFrame> frames(3);
  const char* names[] = {"table2-iss-1.pcd", "table2-round-2.pcd", "clutter-only-0.pcd"};
  for (int k = 0; k < 3; ++k) {
    std::string error;
    assert_true(formats::read_pcd(testing_support::data_path(names[k]), &frames[k], &error));
  }
  // Warm up: the first frame through every path.
  camera.on_new_data(frames[0].view(0, clock.now_us()));
  assert_true(task.process_next(100));
  alloc_counter::arm();
  int processed = 0;
  for (int n = 1; n <= 60; ++n) {
    camera.on_new_data(frames[n % 3].view(static_cast<std::uint64_t>(n), clock.now_us()));
    processed += task.process_next(100) ? 1 : 0;
  }
  task.publish_health();
  const long allocations = alloc_counter::disarm();
  assert_int_equal(processed, 60);
  assert_true(task.counters().found > 10);
  expect_none(allocations, "estimator task, 60 frames");
}

void test_arm_task_cycles_without_allocating(void**) {
  fsw_app::LcmHub hub(g_url);
  assert_true(hub.good());
  hal::ManualClock clock(1000000);
  FakeJoints joints(clock);
  FakeGripper gripper(clock);
  fsw_app::ArmTask task(hub, joints, gripper, arm::PerchConfig{}, clock, 20.0);
  fsw_app::Publisher<hrp::perch_command_t> commands(hub, fsw_app::channel::kPerchCommand);
  task.cycle();  // warm up
  alloc_counter::arm();
  for (int k = 0; k < 200; ++k) {
    clock.advance_us(50000);
    if (k == 10) {
      hrp::perch_command_t c{};
      c.sequence = 1;
      c.command = hrp::perch_command_t::PERCH;
      commands.publish(c);
      // Delivery is the dispatcher thread's work, normally on a thread of
      // its own (LCM's receive buffers are its business): not counted.
      const long so_far = alloc_counter::disarm();
      hub.handle(10);
      alloc_counter::arm();
      alloc_counter::t_allocations = so_far;
    }
    task.cycle();
  }
  const long allocations = alloc_counter::disarm();
  // The command took effect: the arm left STOWED.
  assert_true(task.sequence().state() != arm::PerchState::kStowed);
  expect_none(allocations, "arm task, 200 cycles and a command");
}

// Frames crossing LCM: the frame publisher (the camera's side: copy into
// the message, encode, publish) and the LCM frame source (the estimator
// side: check, decode, copy out to the camera task), given the bytes as
// the dispatcher would. LCM's own receive path is not ours to count.
void test_frames_cross_lcm_without_allocating(void**) {
  fsw_app::LcmHub hub(g_url);
  assert_true(hub.good());
  hal::MonotonicClock clock;
  fsw_app::FrameRing near_ring(3, 224, 171), far_ring(3, 224, 171);
  fsw_app::CameraTask near_task(near_ring, 224, 171), far_task(far_ring, 224, 171);
  fsw_app::FramePublisher publisher(hub, clock, 224, 171, near_task);
  fsw_app::LcmDepthCamera source(hub, 224, 171);
  assert_int_equal(source.initialize(), hal::CameraStatus::kSuccess);
  assert_int_equal(source.register_data_listener(&far_task), hal::CameraStatus::kSuccess);
  assert_int_equal(source.start_capture(), hal::CameraStatus::kSuccess);
  std::vector<formats::PcdFrame> frames(2);
  std::vector<std::vector<std::uint8_t>> encoded(2);
  const char* names[] = {"table2-iss-1.pcd", "clutter-only-0.pcd"};
  for (int k = 0; k < 2; ++k) {
    std::string error;
    assert_true(formats::read_pcd(testing_support::data_path(names[k]), &frames[k], &error));
    hrp::depth_frame_t msg;
    fsw_app::to_msg(frames[k].view(static_cast<std::uint64_t>(k)), &msg);
    encoded[k].resize(static_cast<std::size_t>(msg.getEncodedSize()));
    msg.encode(encoded[k].data(), 0, static_cast<int>(encoded[k].size()));
  }
  publisher.on_new_data(frames[0].view(0, clock.now_us()));  // warm up
  source.deliver(encoded[0].data(), static_cast<std::uint32_t>(encoded[0].size()));
  alloc_counter::arm();
  for (int n = 1; n <= 30; ++n) {
    publisher.on_new_data(frames[n % 2].view(static_cast<std::uint64_t>(n), clock.now_us()));
    source.deliver(encoded[n % 2].data(), static_cast<std::uint32_t>(encoded[n % 2].size()));
  }
  const long allocations = alloc_counter::disarm();
  assert_int_equal(publisher.published(), 31);
  assert_int_equal(far_task.received(), 31);
  assert_int_equal(far_task.corrupt(), 0);
  expect_none(allocations, "frame publisher and LCM frame source, 30 frames of 0.73 MB");
}

}  // namespace

int main() {
  choose_url();
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_estimator_task_processes_frames_without_allocating),
      cmocka_unit_test(test_arm_task_cycles_without_allocating),
      cmocka_unit_test(test_frames_cross_lcm_without_allocating),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
