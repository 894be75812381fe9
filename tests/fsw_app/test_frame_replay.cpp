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
#include "hrp/handrail_estimate_t.hpp"
#include "summary_json.hpp"
#include "test_data.hpp"

namespace {

std::string g_program;

std::string source(const std::string& rel) {
  const char* d = std::getenv("HRP_SOURCE_DIR");
  return std::string(d ? d : ".") + "/" + rel;
}

std::string work_path(const std::string& name) {
  return "/tmp/hrp_replay_" + std::to_string(getpid()) + "_" + name;
}

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

// --- The program.

struct Run {
  int exit_status = -1;
  std::string output;  // stdout and stderr
  testing_support::Summary summary;
  double number(const char* key) const { return summary.number(key); }
};

// Waits for it; its output, exit status and (when named) JSON summary.
Run finish_program(pid_t pid, const std::string& out_path, const std::string& summary = "") {
  Run r;
  r.exit_status = testing_support::wait_for_exit(pid);
  r.output = testing_support::read_text(out_path);
  std::remove(out_path.c_str());
  if (!summary.empty()) {
    std::string error;
    if (!testing_support::read_summary(summary, &r.summary, &error)) {
      print_error("no summary (%s): %s\n%s\n", summary.c_str(), error.c_str(), r.output.c_str());
      fail();
    }
    std::remove(summary.c_str());
  }
  return r;
}

Run run_program(const std::string& program, std::vector<std::string> args,
                const std::string& summary = "") {
  const std::string out_path = work_path("out.txt");
  if (!summary.empty()) std::remove(summary.c_str());
  return finish_program(testing_support::spawn_program(program, std::move(args), out_path),
                        out_path, summary);
}

// fsw_app's arguments: the shipped configuration, quiet, and the summary.
// The budget is 10 s: the recorded and replayed estimates are compared
// exactly, and on a loaded machine (a sanitizer build) a stall could make
// a frame miss the 200 ms budget in one run and not in the other.
std::vector<std::string> fsw_app_args(const std::vector<std::string>& args,
                                      const std::string& summary) {
  std::vector<std::string> all = {"--config", source("fsw_app/config/fsw_app.json"), "--quiet",
                                  "--budget-us", "10000000"};
  all.insert(all.end(), args.begin(), args.end());
  if (!summary.empty()) {
    all.push_back("--summary-json");
    all.push_back(summary);
  }
  return all;
}

Run run_fsw_app(const std::vector<std::string>& args, const std::string& summary = "") {
  return run_program(g_program, fsw_app_args(args, summary), summary);
}

struct Estimate {
  int state = -1;
  double p[3] = {0, 0, 0};
  double q[4] = {0, 0, 0, 0};
};

// HANDRAIL_ESTIMATE by frame id (the first for each frame), and the count
// of DEPTH_FRAME events.
std::map<std::int64_t, Estimate> read_estimates(const std::string& path, int* depth_frames) {
  std::map<std::int64_t, Estimate> out;
  lcm::LogFile log(path, "r");
  assert_true(log.good());
  *depth_frames = 0;
  while (const lcm::LogEvent* e = log.readNextEvent()) {
    if (e->channel == "DEPTH_FRAME") ++*depth_frames;
    if (e->channel != "HANDRAIL_ESTIMATE") continue;
    hrp::handrail_estimate_t m{};  // zeroed: GCC 12 at -O2 cannot see decode() fills it
    assert_true(m.decode(e->data, 0, e->datalen) > 0);
    if (out.count(m.frame_id)) continue;
    Estimate est;
    est.state = m.state;
    for (int k = 0; k < 3; ++k) est.p[k] = m.T_cam_handrail.position_m[k];
    for (int k = 0; k < 4; ++k) est.q[k] = m.T_cam_handrail.quat_wxyz[k];
    out[m.frame_id] = est;
  }
  return out;
}

// Every frame estimated in both runs agrees exactly (same frames, same
// detector); returns how many were compared.
int compare_estimates(const std::map<std::int64_t, Estimate>& a,
                      const std::map<std::int64_t, Estimate>& b) {
  int compared = 0;
  for (const auto& [id, ea] : a) {
    const auto it = b.find(id);
    if (it == b.end()) continue;
    const Estimate& eb = it->second;
    if (ea.state != eb.state) {
      print_error("frame %lld: state %d recorded, %d replayed\n", static_cast<long long>(id),
                  ea.state, eb.state);
      fail();
    }
    for (int k = 0; k < 3; ++k) assert_true(std::fabs(ea.p[k] - eb.p[k]) < 1e-9);
    for (int k = 0; k < 4; ++k) assert_true(std::fabs(ea.q[k] - eb.q[k]) < 1e-9);
    ++compared;
  }
  return compared;
}

// Records a run on the recorded PCD frames (5 fps) with --publish-frames.
std::string record_run() {
  const std::string rec = work_path("rec.lcm");
  const Run r = run_fsw_app(
      {"--hal", "real", "--camera-replay", source("tests/data"), "--tasks", "camera,estimator",
       "--publish-frames", "--duration", "2.5", "--lcm-url", "memq://", "--log", rec},
      work_path("rec.json"));
  assert_int_equal(r.exit_status, 0);
  assert_true(r.number("frames_processed") >= 8);
  return rec;
}

// Every good frame played reached the estimator, and each was estimated or,
// when a stall bunched frames together and the estimator was behind,
// dropped as designed (the oldest first). Most must have been estimated.
void assert_frames_accounted_for(const Run& r, int good_frames) {
  const auto received = static_cast<int>(r.number("frames_received"));
  const auto processed = static_cast<int>(r.number("frames_processed"));
  const auto dropped = static_cast<int>(r.number("frames_dropped"));
  std::printf("%d good frames played: %d received, %d processed, %d dropped\n", good_frames,
              received, processed, dropped);
  assert_int_equal(received, good_frames);
  assert_int_equal(processed + dropped, received);
  assert_true(processed * 3 >= good_frames * 2);
}

struct Replay {
  Run run;
  std::map<std::int64_t, Estimate> estimates;
};

// Replays `log` into an estimator running alone (memq) and reads back what
// it estimated.
Replay replay_into_estimator(const std::string& log, const std::string& name) {
  const std::string replay_log = work_path(name + ".lcm");
  Replay out;
  out.run = run_fsw_app({"--frames-from-log", log, "--lcm-url", "memq://", "--log", replay_log},
                        work_path(name + ".json"));
  std::printf("%s", out.run.output.c_str());
  assert_int_equal(out.run.exit_status, 0);
  int depth_frames = 0;
  out.estimates = read_estimates(replay_log, &depth_frames);
  std::remove(replay_log.c_str());
  return out;
}

// Each frame processed in the replay published one estimate; those of
// frames estimated in both runs agree exactly, and they are most frames
// (either run may have dropped a few when a stall left it behind).
void assert_estimates_agree(const std::map<std::int64_t, Estimate>& recorded, const Replay& replay,
                            int good_frames) {
  const int compared = compare_estimates(recorded, replay.estimates);
  std::printf("%d good frames; %d estimates compared, all equal\n", good_frames, compared);
  assert_int_equal(static_cast<long>(replay.estimates.size()),
                   static_cast<long>(replay.run.number("frames_processed")));
  assert_true(compared * 2 >= good_frames);
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

// An event whose header claims 0x7ffffff0 bytes (found from outside: the
// replay stopped there with no word of damage): LCM's reader takes the rest
// of the file for it and reports the end. The player counts the damage,
// goes back past that event's start, and plays every frame after it.
void test_event_claiming_too_much_is_damage_not_the_end(void**) {
  const std::string rec = record_run();
  const std::string damaged = work_path("claims_too_much.lcm");
  {
    lcm::LogFile in(rec, "r");
    lcm::LogFile out(damaged, "w");
    assert_true(in.good() && out.good());
    int frames = 0;
    while (const lcm::LogEvent* e = in.readNextEvent()) {
      lcm::LogEvent copy = *e;
      assert_int_equal(out.writeEvent(&copy), 0);
      if (e->channel == "DEPTH_FRAME" && ++frames == 4) {
        // sync word, event number, timestamp, channel length, data length
        // (all big-endian), channel: then far fewer bytes than claimed.
        std::fflush(out.getFilePtr());
        const std::uint8_t header[] = {0xED, 0xA1, 0xDA, 0x01, 0,    0,    0,    0,   0, 0,
                                       0,    99,   0,    0,    0,    0,    0,    0,   0, 1,
                                       0,    0,    0,    11,   0x7f, 0xff, 0xff, 0xf0};
        std::fwrite(header, 1, sizeof header, out.getFilePtr());
        std::fwrite("DEPTH_FRAME", 1, 11, out.getFilePtr());
        std::fwrite("short", 1, 5, out.getFilePtr());
      }
    }
  }
  const Replay replay = replay_into_estimator(damaged, "rep_claims");
  const Run& r = replay.run;
  int rec_frames = 0;
  const auto recorded = read_estimates(rec, &rec_frames);
  assert_int_equal(r.number("replay_damaged"), 1);
  assert_int_equal(r.number("replayed_frames"), rec_frames);
  assert_true(r.output.find("damaged log") != std::string::npos);
  assert_estimates_agree(recorded, replay, rec_frames - 1);
  std::remove(damaged.c_str());
  std::remove(rec.c_str());
}

// Recording a run's own frames over udpm (found from outside: 8 of 89
// frames reached the log on the default URL, with no warning): the process
// raises its receive buffer, and the summary says how many of the frames
// it sent the log holds; where the kernel caps the buffer too low, the
// recording refuses to start and says what to set.
void test_recording_frames_over_udpm_loses_none(void**) {
  const std::string url = "udpm://239.255.76.67:" + std::to_string(7500 + getpid() % 90) + "?ttl=0";
  {
    lcm::LCM probe(url);
    if (!probe.good()) {
      std::printf("NOTE: no multicast here (see fsw_app/README.md); not run\n");
      return;
    }
  }
  long rmem_max = -1;
  if (std::FILE* f = std::fopen("/proc/sys/net/core/rmem_max", "r")) {
    if (std::fscanf(f, "%ld", &rmem_max) != 1) rmem_max = -1;
    std::fclose(f);
  }
  const std::string rec = work_path("rec_udpm.lcm");
  const Run r = run_fsw_app(
      {"--hal", "real", "--camera-replay", source("tests/data"), "--tasks", "camera,estimator",
       "--publish-frames", "--duration", "2.5", "--lcm-url", url, "--log", rec},
      rmem_max >= 0 && rmem_max < (4L << 20) ? "" : work_path("rec_udpm.json"));
  if (rmem_max >= 0 && rmem_max < (4L << 20)) {
    std::printf("  rmem_max %ld: the recording must refuse\n", rmem_max);
    assert_int_equal(r.exit_status, 2);
    assert_true(r.output.find("net.core.rmem_max=4194304") != std::string::npos);
    return;
  }
  assert_int_equal(r.exit_status, 0);
  const double published = r.number("frames_published");
  const double logged = r.number("log_depth_frames");
  std::printf("  udpm recording: %.0f of %.0f frames in the log\n", logged, published);
  assert_true(published >= 8);
  assert_true(logged == published);
  int depth_frames = 0;
  read_estimates(rec, &depth_frames);
  assert_int_equal(depth_frames, static_cast<int>(published));
  std::remove(rec.c_str());
}

// A log that cannot be written (found from outside: --log /dev/full
// reported "374 messages" and exit 0) ends with the failure named in the
// summary and exit status 3; the run itself is unharmed.
void test_log_write_failure_is_reported(void**) {
  const Run r = run_fsw_app(
      {"--hal", "real", "--camera-replay", source("tests/data"), "--tasks", "camera,estimator",
       "--publish-frames", "--duration", "1.5", "--lcm-url", "memq://", "--log", "/dev/full"},
      work_path("full.json"));
  assert_int_equal(r.exit_status, 3);
  const std::string failure = r.summary.text("log_failure");
  std::printf("  /dev/full: %s (%.0f written, %.0f lost)\n", failure.c_str(),
              r.number("log_messages"), r.number("log_lost"));
  assert_true(failure.find("No space left on device") != std::string::npos);
  assert_true(r.number("log_lost") > 0);
  assert_true(r.output.find("LCM log /dev/full") != std::string::npos);
  assert_true(r.number("frames_processed") >= 4);
}

// A replay folder with a header claiming 8192 x 8192 points and a
// truncated frame beside good ones (found from outside: 1.32 GB, both
// skipped without a word, exit 0): both are named, nothing large is
// allocated, the good frames play.
void test_replay_folder_names_its_bad_files(void**) {
  const std::string folder = work_path("frames_bad");
  mkdir(folder.c_str(), 0755);
  const std::string good = source("tests/data/table2-iss-1.pcd");
  assert_int_equal(symlink(good.c_str(), (folder + "/a.pcd").c_str()), 0);
  {
    std::FILE* f = std::fopen((folder + "/huge.pcd").c_str(), "w");
    std::fputs(
        "VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 8192\nHEIGHT "
        "8192\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 67108864\nDATA binary\n",
        f);
    std::fclose(f);
    const std::string bytes = testing_support::read_text(good);
    f = std::fopen((folder + "/short.pcd").c_str(), "w");
    std::fwrite(bytes.data(), 1, bytes.size() / 2, f);
    std::fclose(f);
  }
  const Run r = run_fsw_app({"--hal", "real", "--camera-replay", folder, "--tasks",
                             "camera,estimator", "--duration", "1", "--lcm-url", "memq://"},
                            work_path("bad_frames.json"));
  assert_int_equal(r.exit_status, 0);
  assert_true(r.output.find("--camera-replay: 1 frames; skipped:") != std::string::npos);
  assert_true(r.output.find("huge.pcd: WIDTH x HEIGHT 8192 x 8192") != std::string::npos);
  assert_true(r.output.find("short.pcd:") != std::string::npos);
  assert_true(r.number("frames_processed") >= 2);
  for (const char* name : {"a.pcd", "huge.pcd", "short.pcd"}) {
    std::remove((folder + "/" + name).c_str());
  }
  rmdir(folder.c_str());
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
      cmocka_unit_test(test_event_claiming_too_much_is_damage_not_the_end),
      cmocka_unit_test(test_recording_frames_over_udpm_loses_none),
      cmocka_unit_test(test_log_write_failure_is_reported),
      cmocka_unit_test(test_replay_folder_names_its_bad_files),
      cmocka_unit_test(test_bad_replay_requests_are_refused_by_name),
      cmocka_unit_test(test_lcm_logplayer_feeds_an_estimator_process),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
