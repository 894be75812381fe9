// What a recording or a replay must not lose without a word, found by
// testing from outside, each now with the right outcome: a log event that
// claims more bytes than the file holds (the replay stopped there
// silently), the run's own frames recorded over udpm (8 of 89 reached the
// log), a log that cannot be written (reported as written, exit 0), and a
// replay folder with a huge header and a truncated frame (1.32 GB, both
// skipped without a word).
//   argv[1]: the fsw_app program
#include <sys/stat.h>
#include <unistd.h>

#include <lcm/lcm-cpp.hpp>

#include <cstdio>
#include <string>
#include <vector>

#include "cmocka_cpp.hpp"
#include "fsw_app_runs.hpp"

namespace {

using namespace fsw_app_runs;

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
// reported "374 messages" and exit 0, then "18 messages" recorded when no
// byte reached the device) ends with the failure named in the summary and
// exit status 3, nothing counted as recorded; the run itself is unharmed.
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
  assert_true(r.number("log_messages") == 0.0);
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

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s FSW_APP\n", argv[0]);
    return 2;
  }
  g_program = argv[1];
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_event_claiming_too_much_is_damage_not_the_end),
      cmocka_unit_test(test_recording_frames_over_udpm_loses_none),
      cmocka_unit_test(test_log_write_failure_is_reported),
      cmocka_unit_test(test_replay_folder_names_its_bad_files),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
