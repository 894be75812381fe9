// Depth frames over LCM and a recorded run replayed into the estimator.
// In process (memq://): DEPTH_FRAME messages round-trip exactly; malformed
// bytes are named and never reach LCM's decoder; the LCM frame source drops
// and counts them while the good frames around them go through. The
// program (fsw_app, argv[1]): a run on recorded PCD frames is logged with
// its frames, replayed with --frames-from-log into an estimator running on
// its own, and the replay's estimates match the recording's frame by
// frame; a damaged log (a truncated frame, junk between events) replays
// the rest with the bad frame counted; bad options and files are refused
// with a message naming them. Over udpm, when the host has multicast:
// lcm-logplayer feeds an estimator-only fsw_app.
//   argv[1]: the fsw_app program
#include <sys/stat.h>
#include <unistd.h>

#include <lcm/lcm-cpp.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "child_process.hpp"
#include "cmocka_cpp.hpp"
#include "formats/pcd_io.hpp"
#include "fsw_app/camera_task.hpp"
#include "fsw_app/depth_frame_msg.hpp"
#include "fsw_app/frame_publisher.hpp"
#include "fsw_app/lcm_depth_camera.hpp"
#include "fsw_app_runs.hpp"
#include "hrp/handrail_estimate_t.hpp"
#include "summary_json.hpp"
#include "test_data.hpp"

namespace {

using namespace fsw_app_runs;

formats::PcdFrame load_frame(const char* name) {
  formats::PcdFrame f;
  std::string error;
  assert_true(formats::read_pcd(testing_support::data_path(name), &f, &error));
  return f;
}

std::vector<std::uint8_t> encode(const hrp::depth_frame_t& msg) {
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(msg.getEncodedSize()));
  assert_int_equal(msg.encode(bytes.data(), 0, static_cast<int>(bytes.size())),
                   static_cast<int>(bytes.size()));
  return bytes;
}

void test_depth_frame_round_trips_exactly(void**) {
  formats::PcdFrame pcd = load_frame("table2-iss-1.pcd");
  std::vector<hal::DepthPoint> points = pcd.points;
  points[5].gray_value = 65535;  // the top of the unsigned range travels as int16
  points[6].confidence = 255;
  const hal::DepthFrame frame{42, 123456789, pcd.width, pcd.height, points.data()};
  hrp::depth_frame_t msg;
  fsw_app::to_msg(frame, &msg);
  const std::vector<std::uint8_t> bytes = encode(msg);
  assert_int_equal(bytes.size(), fsw_app::depth_frame_encoded_size(points.size()));
  std::printf("a %u x %u frame encodes to %zu bytes\n", pcd.width, pcd.height, bytes.size());

  hrp::depth_frame_t back;
  assert_int_equal(fsw_app::decode_depth_frame(bytes.data(), bytes.size(), 224 * 171, &back),
                   fsw_app::FrameMsgStatus::kOk);
  std::vector<hal::DepthPoint> out(points.size());
  hal::DepthFrame f;
  fsw_app::from_msg(back, out.data(), &f);
  assert_int_equal(f.frame_id, 42);
  assert_int_equal(f.capture_time_us, 123456789);
  assert_int_equal(f.width, pcd.width);
  assert_int_equal(f.height, pcd.height);
  for (std::size_t k = 0; k < points.size(); ++k) {
    const hal::DepthPoint& a = points[k];
    const hal::DepthPoint& b = out[k];
    // Bit for bit (NaN included): the replay must see what the camera gave.
    assert_memory_equal(&a.x_m, &b.x_m, 4 * sizeof(float));
    assert_int_equal(a.gray_value, b.gray_value);
    assert_int_equal(a.confidence, b.confidence);
  }
}

void test_malformed_frame_bytes_are_named(void**) {
  const formats::PcdFrame pcd = load_frame("table2-iss-1.pcd");
  hrp::depth_frame_t msg;
  fsw_app::to_msg(pcd.view(7, 1000), &msg);
  const std::vector<std::uint8_t> good = encode(msg);
  hrp::depth_frame_t out;
  using fsw_app::FrameMsgStatus;
  auto status = [&](const std::vector<std::uint8_t>& b, std::size_t max_points = 224 * 171) {
    return fsw_app::decode_depth_frame(b.data(), b.size(), max_points, &out);
  };
  auto put32 = [](std::vector<std::uint8_t>* b, std::size_t at, std::int32_t v) {
    for (int k = 0; k < 4; ++k) (*b)[at + k] = static_cast<std::uint8_t>(v >> (24 - 8 * k));
  };
  assert_int_equal(status(good), FrameMsgStatus::kOk);
  assert_int_equal(status(std::vector<std::uint8_t>(good.begin(), good.begin() + 30)),
                   FrameMsgStatus::kTruncated);
  assert_int_equal(status(std::vector<std::uint8_t>(good.begin(), good.end() - 1)),
                   FrameMsgStatus::kTruncated);
  std::vector<std::uint8_t> longer = good;
  longer.push_back(0);
  assert_int_equal(status(longer), FrameMsgStatus::kTrailingBytes);
  std::vector<std::uint8_t> b = good;
  b[0] ^= 0xff;  // the fingerprint
  assert_int_equal(status(b), FrameMsgStatus::kWrongType);
  b = good;
  put32(&b, 32, 225);  // width no longer matches the point count
  assert_int_equal(status(b), FrameMsgStatus::kBadSize);
  b = good;
  put32(&b, 40, -5);  // a negative count: LCM would size its arrays from it
  put32(&b, 32, -1);
  put32(&b, 36, 5);
  assert_int_equal(status(b), FrameMsgStatus::kBadSize);
  b = good;
  put32(&b, 32, 40000);  // a huge frame with a consistent header
  put32(&b, 36, 40000);
  put32(&b, 40, 1600000000);
  assert_int_equal(status(b), FrameMsgStatus::kTooLarge);
  assert_int_equal(status(good, 1000), FrameMsgStatus::kTooLarge);
  assert_int_equal(fsw_app::decode_depth_frame(nullptr, 0, 10, &out), FrameMsgStatus::kTruncated);
  assert_string_equal(fsw_app::to_string(FrameMsgStatus::kTrailingBytes), "TRAILING_BYTES");
}

// Frames from a camera, through the frame publisher, over LCM into the
// LCM frame source and a camera task: what a split estimator process sees.
void test_frames_cross_lcm_and_bad_messages_are_counted(void**) {
  fsw_app::LcmHub hub("memq://");
  assert_true(hub.good());
  hal::MonotonicClock clock;
  fsw_app::FrameRing ring(3, 224, 171);
  fsw_app::CameraTask far_task(ring, 224, 171);
  fsw_app::LcmDepthCamera source(hub, 224, 171);
  assert_int_equal(source.initialize(), hal::CameraStatus::kSuccess);
  assert_int_equal(source.register_data_listener(&far_task), hal::CameraStatus::kSuccess);
  assert_int_equal(source.start_capture(), hal::CameraStatus::kSuccess);

  fsw_app::FrameRing near_ring(3, 224, 171);
  fsw_app::CameraTask near_task(near_ring, 224, 171);
  fsw_app::FramePublisher publisher(hub, clock, 224, 171, near_task);
  const formats::PcdFrame pcd = load_frame("table2-round-2.pcd");
  publisher.on_new_data(pcd.view(11, 5000));
  assert_int_equal(near_task.received(), 1);  // the local path comes first
  assert_int_equal(publisher.published(), 1);
  while (hub.handle(0) > 0) {
  }
  assert_int_equal(far_task.received(), 1);
  hal::DepthFrame got;
  std::vector<hal::DepthPoint> points(224 * 171);
  assert_int_equal(ring.pop_newest(&got, points.data()), fsw_app::RingStatus::kOk);
  assert_int_equal(got.frame_id, 11);
  assert_int_equal(got.capture_time_us, 5000);
  for (std::size_t k = 0; k < pcd.points.size(); ++k) {
    assert_memory_equal(&points[k].x_m, &pcd.points[k].x_m, 4 * sizeof(float));
    assert_int_equal(points[k].gray_value, pcd.points[k].gray_value);
    assert_int_equal(points[k].confidence, pcd.points[k].confidence);
  }

  // A truncated message and one of another type on the channel: dropped,
  // counted by the camera task as corrupt, the reason kept; then a good
  // frame still goes through.
  hrp::depth_frame_t msg;
  fsw_app::to_msg(pcd.view(12, 6000), &msg);
  const std::vector<std::uint8_t> bytes = encode(msg);
  hub.publish_raw(fsw_app::channel::kDepthFrame, bytes.data(), bytes.size() / 2);
  const std::uint8_t junk[64] = {1, 2, 3};  // long enough for a header, not this type
  hub.publish_raw(fsw_app::channel::kDepthFrame, junk, sizeof junk);
  hub.publish_raw(fsw_app::channel::kDepthFrame, bytes.data(), bytes.size());
  while (hub.handle(0) > 0) {
  }
  assert_int_equal(source.messages_rejected(), 2);
  assert_int_equal(source.last_rejection(), fsw_app::FrameMsgStatus::kWrongType);
  assert_int_equal(far_task.corrupt(), 2);
  assert_int_equal(far_task.received(), 2);
  assert_int_equal(source.frames_delivered(), 2);

  // Before capture starts and after it stops, messages are ignored.
  assert_int_equal(source.stop_capture(), hal::CameraStatus::kSuccess);
  hub.publish_raw(fsw_app::channel::kDepthFrame, bytes.data(), bytes.size());
  while (hub.handle(0) > 0) {
  }
  assert_int_equal(far_task.received(), 2);
}

void test_recorded_run_replays_into_the_estimator_alone(void**) {
  const std::string rec = record_run();
  const Replay replay = replay_into_estimator(rec, "rep");
  const Run& r = replay.run;
  const auto& replayed = replay.estimates;
  int rec_frames = 0;
  const auto recorded = read_estimates(rec, &rec_frames);
  assert_int_equal(r.number("replayed_frames"), rec_frames);
  assert_int_equal(r.number("replayed_bad_frames"), 0);
  assert_int_equal(r.number("frames_corrupt"), 0);
  assert_frames_accounted_for(r, rec_frames);
  // Capture times were moved to the replay's clock: latencies are real.
  // Left on the recording's clock, every frame's would exceed the 2.5 s
  // the recording took, as it ended before the replay began.
  assert_true(r.number("estimator_longest_latency_ms") >= 0.0);
  assert_true(r.number("estimator_longest_latency_ms") < 2000.0);
  assert_estimates_agree(recorded, replay, rec_frames);
  int found = 0;
  for (const auto& [id, e] : replayed) found += e.state != 0 ? 1 : 0;
  assert_true(found >= 2);  // not only "no handrail" frames
  std::remove(rec.c_str());
}

// A log with its third frame cut short and junk bytes after its fifth: the
// short frame is played and counted as corrupt; the junk is skipped to the
// next event (LCM's reader drops the fifth frame with it, as it cannot
// tell where that event ended); the others replay and agree.
void test_damaged_log_replays_the_rest(void**) {
  const std::string rec = record_run();
  const std::string damaged = work_path("damaged.lcm");
  {
    lcm::LogFile in(rec, "r");
    lcm::LogFile out(damaged, "w");
    assert_true(in.good() && out.good());
    int frames = 0;
    while (const lcm::LogEvent* e = in.readNextEvent()) {
      const bool frame = e->channel == "DEPTH_FRAME";
      frames += frame ? 1 : 0;
      lcm::LogEvent copy = *e;
      if (frame && frames == 3) copy.datalen = e->datalen / 2;
      assert_int_equal(out.writeEvent(&copy), 0);
      if (frame && frames == 5) {
        // Bytes that are no event at all: the reader must find the next.
        std::fflush(out.getFilePtr());
        const char junk[] = "not an LCM event, only junk bytes";
        std::fwrite(junk, 1, sizeof junk, out.getFilePtr());
      }
    }
  }
  const Replay replay = replay_into_estimator(damaged, "rep_damaged");
  const Run& r = replay.run;
  const auto& replayed = replay.estimates;
  int rec_frames = 0;
  const auto recorded = read_estimates(rec, &rec_frames);
  assert_int_equal(r.number("replay_damaged"), 1);
  assert_int_equal(r.number("replayed_frames"), rec_frames - 1);
  assert_int_equal(r.number("replayed_bad_frames"), 1);
  assert_int_equal(r.number("frames_corrupt"), 1);
  assert_frames_accounted_for(r, rec_frames - 2);
  assert_true(r.output.find("TRUNCATED") != std::string::npos);
  assert_estimates_agree(recorded, replay, rec_frames - 2);
  assert_true(replayed.count(4) == 0);  // frame ids count from 0: the fifth frame
  std::remove(damaged.c_str());
  std::remove(rec.c_str());
}

void test_bad_replay_requests_are_refused_by_name(void**) {
  Run r = run_fsw_app({"--frames-from-log", work_path("missing.lcm")});
  assert_int_equal(r.exit_status, 2);
  assert_true(r.output.find("missing.lcm: cannot open it as an LCM log") != std::string::npos);

  // A log without frames says how to record one.
  const std::string no_frames = work_path("no_frames.lcm");
  {
    lcm::LogFile out(no_frames, "w");
    lcm::LogEvent e{};
    std::uint8_t data[8] = {};
    e.channel = "ROBOT_POSE";
    e.datalen = sizeof data;
    e.data = data;
    assert_int_equal(out.writeEvent(&e), 0);
  }
  r = run_fsw_app({"--frames-from-log", no_frames});
  assert_int_equal(r.exit_status, 2);
  assert_true(r.output.find("no DEPTH_FRAME message") != std::string::npos);
  assert_true(r.output.find("--publish-frames") != std::string::npos);
  std::remove(no_frames.c_str());

  // A text file is not a log.
  r = run_fsw_app({"--frames-from-log", source("fsw_app/config/fsw_app.json")});
  assert_int_equal(r.exit_status, 2);

  r = run_fsw_app({"--frames-from-log", no_frames, "--tasks", "camera,estimator"});
  assert_int_equal(r.exit_status, 2);
  assert_true(r.output.find("not with the camera task") != std::string::npos);
  r = run_fsw_app({"--tasks", "estimator,gripper"});
  assert_int_equal(r.exit_status, 2);
  assert_true(r.output.find("unknown task \"gripper\"") != std::string::npos);
  r = run_fsw_app({"--tasks", "camera", "--hal", "sim"});
  assert_int_equal(r.exit_status, 2);
  assert_true(r.output.find("needs --scenario FILE for the camera task") != std::string::npos);
}

// lcm-logplayer plays the recorded frames on udpm into an estimator-only
// fsw_app in another process.
void test_lcm_logplayer_feeds_an_estimator_process(void**) {
  const std::string url = "udpm://239.255.76.67:" + std::to_string(7600 + getpid() % 90) +
                          "?ttl=0&recv_buf_size=4194304";
  {
    lcm::LCM probe(url);
    if (!probe.good()) {
      std::printf("NOTE: no multicast here (see fsw_app/README.md); not run\n");
      return;
    }
  }
  const std::string rec = record_run();
  const std::string live = work_path("live.lcm");
  const std::string summary = work_path("live.json");
  const std::string out_path = work_path("live.txt");
  const pid_t pid = testing_support::spawn_program(
      g_program,
      fsw_app_args({"--tasks", "estimator", "--lcm-url", url, "--duration", "6", "--log", live},
                   summary),
      out_path);
  sleep(1);  // its subscription in place
  const Run player = run_program("lcm-logplayer", {"-e", "DEPTH_FRAME|ROBOT_POSE", "-l", url, rec});
  assert_int_equal(player.exit_status, 0);
  assert_int_equal(finish_program(pid, out_path, summary).exit_status, 0);
  int rec_frames = 0, live_frames = 0;
  const int compared =
      compare_estimates(read_estimates(rec, &rec_frames), read_estimates(live, &live_frames));
  // UDP may lose a frame whose fragments overflow a small kernel buffer
  // (net.core.rmem_max caps recv_buf_size); those that arrive must agree.
  std::printf("lcm-logplayer over udpm: %d of %d frames estimated, all equal\n", compared,
              rec_frames);
  assert_true(compared >= 1);
  std::remove(live.c_str());
  std::remove(rec.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s FSW_APP\n", argv[0]);
    return 2;
  }
  g_program = argv[1];
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_depth_frame_round_trips_exactly),
      cmocka_unit_test(test_malformed_frame_bytes_are_named),
      cmocka_unit_test(test_frames_cross_lcm_and_bad_messages_are_counted),
      cmocka_unit_test(test_recorded_run_replays_into_the_estimator_alone),
      cmocka_unit_test(test_damaged_log_replays_the_rest),
      cmocka_unit_test(test_bad_replay_requests_are_refused_by_name),
      cmocka_unit_test(test_lcm_logplayer_feeds_an_estimator_process),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
