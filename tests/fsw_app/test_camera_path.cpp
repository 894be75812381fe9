// Which path the frames took, as fsw_app reports it: --hal sim
// runs the raw path by default (the raw renderer's phase frames through the
// robot's ToF processing), --camera depth the depth renderer, and recorded
// frames are "replay"; the summary JSON names the path and the processing's
// cost. A calibration file the processing cannot read stops the start.
#include <cstdio>
#include <string>

#include "fsw_app_runs.hpp"

using namespace fsw_app_runs;

namespace {

const formats::JsonValue* camera_key(const Run& r, const char* key) {
  const formats::JsonValue* camera = r.summary.json.find("camera");
  return camera && camera->is_object() ? camera->find(key) : nullptr;
}
std::string camera_text(const Run& r, const char* key) {
  const formats::JsonValue* v = camera_key(r, key);
  return v && v->is_string() ? v->text : "";
}
double camera_number(const Run& r, const char* key) {
  const formats::JsonValue* v = camera_key(r, key);
  return v && v->is_number() ? v->number : -2.0;
}

std::vector<std::string> sim_args(std::vector<std::string> extra) {
  std::vector<std::string> a = {"--hal",      "sim",
                                "--scenario", source("sim_hal/scenarios/table2-iss.json"),
                                "--tasks",    "camera,estimator",
                                "--duration", "3",
                                "--lcm-url",  "memq://"};
  a.insert(a.end(), extra.begin(), extra.end());
  return a;
}

void expect_exit(const Run& r, int status) {
  if (r.exit_status != status) print_error("exit %d:\n%s\n", r.exit_status, r.output.c_str());
  assert_int_equal(r.exit_status, status);
}

void test_sim_runs_the_raw_path_by_default(void**) {
  const std::string summary = work_path("raw.json");
  const Run r = run_fsw_app(sim_args({}), summary);
  expect_exit(r, 0);
  assert_string_equal(camera_text(r, "path").c_str(), "raw");
  assert_true(camera_number(r, "tof_median_us") > 0.0);
  assert_true(camera_number(r, "tof_frames") >= 5.0);
  assert_true(camera_number(r, "tof_frames_dropped") == 0.0);
  assert_true(camera_number(r, "tof_valid_pixel_share") > 0.5);
  assert_true(r.number("frames_processed") >= 5.0);
}

void test_depth_renderer_stays_selectable(void**) {
  const std::string summary = work_path("depth.json");
  const Run r = run_fsw_app(sim_args({"--camera", "depth"}), summary);
  expect_exit(r, 0);
  assert_string_equal(camera_text(r, "path").c_str(), "depth");
  assert_true(camera_number(r, "tof_median_us") == -1.0);
  assert_true(camera_number(r, "tof_frames") == -1.0);
  assert_true(r.number("frames_processed") >= 5.0);
}

void test_recorded_frames_are_the_replay_path(void**) {
  const std::string summary = work_path("replay.json");
  const Run r = run_fsw_app({"--hal", "real", "--camera-replay", source("tests/data"), "--tasks",
                             "camera,estimator", "--duration", "2", "--lcm-url", "memq://"},
                            summary);
  expect_exit(r, 0);
  assert_string_equal(camera_text(r, "path").c_str(), "replay");
  assert_true(camera_number(r, "tof_median_us") == -1.0);
}

void test_unusable_calibration_file_stops_the_start(void**) {
  // Where the unit's file cannot go, the processing has nothing to read:
  // refused at start-up with the file named.
  const std::string nowhere = "/nonexistent-hrp-dir/pico-flexx.json";
  Run r = run_fsw_app(sim_args({"--tof-calibration", nowhere}));
  expect_exit(r, 2);
  assert_true(r.output.find(nowhere) != std::string::npos);
  r = run_fsw_app(sim_args({"--camera", "phase"}));
  expect_exit(r, 2);
  assert_true(r.output.find("--camera is raw, depth, usb or royale") != std::string::npos);
  r = run_fsw_app({"--hal", "real", "--camera-replay", source("tests/data"), "--camera", "raw"});
  expect_exit(r, 2);
  assert_true(r.output.find("--hal sim") != std::string::npos);
}

void test_calibration_file_is_kept_where_asked(void**) {
  // The simulated unit's file, as the processing read it, stays for a look.
  const std::string path = work_path("unit.json");
  std::remove(path.c_str());
  const Run r = run_fsw_app(sim_args({"--tof-calibration", path, "--duration", "1"}));
  expect_exit(r, 0);
  const std::string text = testing_support::read_text(path);
  assert_true(text.find("\"format_version\": 1") != std::string::npos);
  std::remove(path.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s FSW_APP\n", argv[0]);
    return 2;
  }
  g_program = argv[1];
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_sim_runs_the_raw_path_by_default),
      cmocka_unit_test(test_depth_renderer_stays_selectable),
      cmocka_unit_test(test_recorded_frames_are_the_replay_path),
      cmocka_unit_test(test_unusable_calibration_file_stops_the_start),
      cmocka_unit_test(test_calibration_file_is_kept_where_asked),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
