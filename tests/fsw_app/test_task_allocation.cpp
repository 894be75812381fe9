// The tasks' cycles allocate nothing once running, publishing included:
// the estimator task processing recorded frames (ring, detector, tracker,
// HANDRAIL_ESTIMATE) and the arm task's cycle (command and approach
// mailboxes, perch sequence, ARM_STATE), and frames crossing LCM (the
// frame publisher and the LCM frame source) and the localization task's
// cycle (IMU samples, GP poses and handrail estimates into the filter,
// ROBOT_POSE out), counted on the calling thread,
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
#include "fsw_app/localization_task.hpp"
#include "fsw_app/msg_convert.hpp"
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
  hal::ManualClock clock(1000000);
  fsw_app::LcmHub hub(g_url, clock);
  assert_true(hub.good());
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
  source.deliver(encoded[0].data(), static_cast<std::uint32_t>(encoded[0].size()),
                 fsw_app::kNoReceiverClock);
  alloc_counter::arm();
  for (int n = 1; n <= 30; ++n) {
    publisher.on_new_data(frames[n % 2].view(static_cast<std::uint64_t>(n), clock.now_us()));
    source.deliver(encoded[n % 2].data(), static_cast<std::uint32_t>(encoded[n % 2].size()),
                   fsw_app::kNoReceiverClock);
  }
  const long allocations = alloc_counter::disarm();
  assert_int_equal(publisher.published(), 31);
  assert_int_equal(far_task.received(), 31);
  assert_int_equal(far_task.corrupt(), 0);
  expect_none(allocations, "frame publisher and LCM frame source, 30 frames of 0.73 MB");
}

// At rest 0.8 m in front of a handrail on the wall x = 0, facing it: IMU
// samples at 62.5 Hz, a GP pose each second, a BE handrail estimate at
// 5 Hz, the task cycling at 100 Hz; delivery (the dispatcher's work) is not
// counted, the cycles are.
void test_localization_task_cycles_without_allocating(void**) {
  hal::ManualClock clock(1000000);
  fsw_app::LcmHub hub(g_url, clock);
  assert_true(hub.good());
  fsw_app::LocalizationTaskConfig cfg;
  fsw_app::LocalizationTask task(hub, cfg, clock);
  fsw_app::Publisher<hrp::imu_sample_t> imu(hub, fsw_app::channel::kImuSample);
  fsw_app::Publisher<hrp::gp_pose_t> gp(hub, fsw_app::channel::kGpPose);
  fsw_app::Publisher<hrp::handrail_estimate_t> handrail(hub, fsw_app::channel::kHandrailEstimate);
  Eigen::Isometry3d T_world_body = Eigen::Isometry3d::Identity();
  T_world_body.translation() << 0.8, 0.0, -0.06;
  Eigen::Isometry3d T_world_handrail = Eigen::Isometry3d::Identity();
  T_world_handrail.translation() << 0.061, 0.0, 0.0;
  const Eigen::Isometry3d T_cam_handrail =
      (T_world_body * cfg.filter.T_body_cam).inverse() * T_world_handrail;
  hrp::imu_sample_t s{};
  hrp::gp_pose_t g{};
  fsw_app::to_msg(T_world_body, &g.T_world_body);
  for (int r = 0; r < 6; ++r) g.covariance[r][r] = r < 3 ? 4e-4 : 1e-4;
  hrp::handrail_estimate_t e{};
  e.state = hrp::handrail_estimate_t::STATE_BE;
  e.num_ends = 2;
  fsw_app::to_msg(T_cam_handrail, &e.T_cam_handrail);
  fsw_app::to_msg(cfg.filter.T_body_cam * T_cam_handrail, &e.T_body_handrail);
  fsw_app::to_msg(Eigen::Isometry3d::Identity(), &e.T_body_target);
  const auto deliver = [&] {
    const long so_far = alloc_counter::disarm();
    while (hub.handle(5) > 0) {
    }
    alloc_counter::arm();
    alloc_counter::t_allocations = so_far;
  };
  std::int64_t next_imu_us = clock.now_us();
  long allocations = 0;
  alloc_counter::arm();
  for (int k = 0; k < 600; ++k) {
    clock.advance_us(10000);
    const std::int64_t now = clock.now_us();
    bool sent = false;
    if (now >= next_imu_us) {
      s.utime = now;
      ++s.seq;
      imu.publish(s);
      next_imu_us += 16000;
      sent = true;
    }
    if (k % 100 == 50) {
      g.utime = now;
      g.capture_utime = now - 150000;
      gp.publish(g);
      sent = true;
    }
    if (k % 20 == 10 && k > 150) {
      e.utime = now;
      e.capture_utime = now - 100000;
      ++e.frame_id;
      handrail.publish(e);
      sent = true;
    }
    if (sent) deliver();
    task.step();
  }
  allocations = alloc_counter::disarm();
  assert_true(task.filter().initialized());
  assert_true(task.filter().handrail_map().valid);
  assert_true(task.counters().poses_published > 300);
  expect_none(allocations, "localization task, 600 cycles");
}

}  // namespace

int main() {
  choose_url();
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_estimator_task_processes_frames_without_allocating),
      cmocka_unit_test(test_arm_task_cycles_without_allocating),
      cmocka_unit_test(test_frames_cross_lcm_without_allocating),
      cmocka_unit_test(test_localization_task_cycles_without_allocating),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
