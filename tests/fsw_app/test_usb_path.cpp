// The hardware-in-loop perch with every depth frame through the USB driver
// fsw_app --hal sim --camera usb renders the world into the
// emulated Pico Flexx (umockdev), and the robot's driver reads it through
// real libusb, then the ToF processing, the camera task, the estimator. The
// perch must land within 1 cm with no frame lost; pulling the cable and
// halting the stream endpoint mid-approach must be recovered from and
// counted; the USB faults are refused on any other path; and on the robot
// (--hal real) a missing camera stops the start with a reason. The same
// perch through the royale API (--camera royale: hal::DepthCamera on
// royale, here the project's royale on the same driver).
#include <cstdio>
#include <initializer_list>
#include <string>

#include "fsw_app_runs.hpp"

using namespace fsw_app_runs;

namespace {

// A number or text inside the summary's nested objects; -1 / "" when missing.
double nested_number(const Run& r, std::initializer_list<const char*> path) {
  return r.summary.number_at(path);
}
std::string nested_text(const Run& r, std::initializer_list<const char*> path) {
  return r.summary.text_at(path);
}

std::vector<std::string> usb_perch_args(std::vector<std::string> extra) {
  std::vector<std::string> a = {
      "--hal",   "sim",       "--scenario", source("sim_hal/scenarios/table2-iss.json"),
      "--perch", "--timeout", "60",         "--lcm-url",
      "memq://"};
  // The path is usb unless the extra arguments name another.
  bool camera_named = false;
  for (const std::string& e : extra) camera_named = camera_named || e == "--camera";
  if (!camera_named) a.insert(a.end(), {"--camera", "usb"});
  a.insert(a.end(), extra.begin(), extra.end());
  return a;
}

bool perched_within_1cm(const Run& r) {
  return r.summary.flag("perched") && r.summary.flag("success");
}

// A real-time run on a shared host: a perch that failed while the arm loop
// or the frames were stalled by the host is run again (at most twice), as
// fsw_app_hil_faults does; one that failed on time fails at once.
bool host_stalled(const Run& r) {
  return r.number("arm_longest_gap_ms") > 150.0 || r.number("estimator_longest_latency_ms") > 200.0;
}
Run perch_over_usb(const std::string& name, std::vector<std::string> extra) {
  const std::string summary = work_path(name + ".json");
  Run r = run_fsw_app(usb_perch_args(extra), summary);
  for (int again = 0; again < 2 && !perched_within_1cm(r) && host_stalled(r); ++again) {
    std::printf("  NOTE: the host stalled the run (arm loop %.0f ms); running it again\n",
                r.number("arm_longest_gap_ms"));
    r = run_fsw_app(usb_perch_args(extra), summary);
  }
  if (!perched_within_1cm(r)) print_error("exit %d:\n%s\n", r.exit_status, r.output.c_str());
  if (nested_text(r, {"camera", "path"}) == "royale") {
    std::printf("  %s: %s, grasp %.1f mm, %.0f frames delivered through royale\n", name.c_str(),
                r.summary.text("arm_state").c_str(), 1e3 * r.number("grasp_error_m"),
                nested_number(r, {"camera", "royale", "frames_delivered"}));
    return r;
  }
  std::printf("  %s: %s, grasp %.1f mm, %.0f frames delivered over USB, %.0f lost, ToF %.0f us\n",
              name.c_str(), r.summary.text("arm_state").c_str(), 1e3 * r.number("grasp_error_m"),
              nested_number(r, {"camera", "usb", "frames_delivered"}),
              nested_number(r, {"camera", "frames_lost"}),
              nested_number(r, {"camera", "tof_median_us"}));
  return r;
}

void test_perch_through_the_usb_driver(void**) {
  const Run r = perch_over_usb("usb-clean", {"--seed", "3"});
  assert_int_equal(r.exit_status, 0);
  assert_true(perched_within_1cm(r));
  assert_string_equal(nested_text(r, {"camera", "path"}).c_str(), "usb");
  // Every frame the camera made reached the processing and the estimator.
  const double delivered = nested_number(r, {"camera", "usb", "frames_delivered"});
  assert_true(delivered >= 20.0);
  assert_true(nested_number(r, {"camera", "frames_lost"}) == 0.0);
  assert_true(nested_number(r, {"camera", "usb", "frames_made_by_camera"}) == delivered);
  assert_true(nested_number(r, {"camera", "tof_frames"}) == delivered);
  assert_true(nested_number(r, {"camera", "tof_frames_dropped"}) == 0.0);
  assert_true(nested_number(r, {"camera", "tof_median_us"}) > 0.0);
  assert_true(r.number("frames_received") == delivered);
  assert_true(r.number("frames_corrupt") == 0.0);
  assert_true(nested_number(r, {"camera", "usb", "unplugs"}) == 0.0);
  assert_true(nested_number(r, {"camera", "usb", "stalls"}) == 0.0);
  // The state as the run ended (streaming), not the one stopping leaves.
  assert_string_equal(nested_text(r, {"camera", "usb", "state"}).c_str(), "STREAMING");
}

void test_perch_rides_out_an_unplug_and_a_stall(void**) {
  // The cable out for half a second 2 s into the approach, the stream
  // endpoint halted 4 s later, 5 frames corrupted on the wire after that.
  const Run r = perch_over_usb("usb-faults", {"--seed", "4", "--fault", "usb-unplug@2", "--fault",
                                              "usb-stall@6", "--fault", "corrupt-frames@8"});
  assert_int_equal(r.exit_status, 0);
  assert_true(perched_within_1cm(r));
  assert_true(nested_number(r, {"camera", "usb", "unplugs"}) == 1.0);
  assert_true(nested_number(r, {"camera", "usb", "replugs"}) == 1.0);
  assert_true(nested_number(r, {"camera", "usb", "stalls"}) >= 1.0);
  assert_true(nested_number(r, {"camera", "usb", "clear_halts"}) >= 1.0);
  // The corrupt frames were refused by the driver, not handed on: the
  // camera task saw none.
  assert_true(nested_number(r, {"camera", "usb", "frames_corrupt"}) == 5.0);
  assert_true(nested_number(r, {"camera", "frames_lost"}) >= 5.0);
  assert_true(r.number("frames_corrupt") == 0.0);
  assert_true(nested_text(r, {"camera", "usb", "state"}) != "LOST");
}

void test_perch_through_royale(void**) {
  const Run r = perch_over_usb("royale-clean", {"--seed", "5", "--camera", "royale"});
  assert_int_equal(r.exit_status, 0);
  assert_true(perched_within_1cm(r));
  assert_string_equal(nested_text(r, {"camera", "path"}).c_str(), "royale");
  const double delivered = nested_number(r, {"camera", "royale", "frames_delivered"});
  const double made = nested_number(r, {"camera", "royale", "frames_made_by_camera"});
  std::printf("  royale: %.0f frames delivered of %.0f made, capture clock %s\n", delivered, made,
              nested_text(r, {"camera", "royale", "capture_clock"}).c_str());
  assert_true(delivered >= 20.0);
  // Every frame made reached the camera task, but one the camera made as
  // the run stopped.
  assert_true(made - delivered <= 1.0);
  assert_true(nested_number(r, {"camera", "royale", "frames_malformed"}) == 0.0);
  assert_string_equal(nested_text(r, {"camera", "royale", "capture_clock"}).c_str(), "SAME");
  assert_true(r.number("frames_received") == delivered);
  assert_true(r.number("frames_corrupt") == 0.0);
}

void test_usb_faults_need_the_usb_path(void**) {
  Run r = run_fsw_app({"--hal", "sim", "--scenario", source("sim_hal/scenarios/table2-iss.json"),
                       "--perch", "--fault", "usb-unplug"});
  assert_int_equal(r.exit_status, 2);
  assert_true(r.output.find("--camera usb") != std::string::npos);
  r = run_fsw_app({"--hal", "sim", "--scenario", source("sim_hal/scenarios/table2-iss.json"),
                   "--camera", "usb", "--tof-calibration", work_path("unit.json")});
  assert_int_equal(r.exit_status, 2);
  assert_true(r.output.find("read from the camera") != std::string::npos);
}

void test_robot_without_a_camera_says_so(void**) {
  // --hal real opens the Pico Flexx driver: this machine has no such
  // camera, so the start stops with the driver's status and what to check.
  const Run r = run_fsw_app(
      {"--hal", "real", "--tasks", "camera,estimator", "--duration", "1", "--lcm-url", "memq://"});
  if (r.exit_status != 1) print_error("exit %d:\n%s\n", r.exit_status, r.output.c_str());
  assert_int_equal(r.exit_status, 1);
  assert_true(r.output.find("Pico Flexx") != std::string::npos);
  assert_true(r.output.find("--camera-replay") != std::string::npos);
}

void test_robot_royale_without_a_camera_says_so(void**) {
  Run r = run_fsw_app({"--hal", "real", "--camera", "royale", "--tasks", "camera,estimator",
                       "--duration", "1", "--lcm-url", "memq://"});
  if (r.exit_status != 1) print_error("exit %d:\n%s\n", r.exit_status, r.output.c_str());
  assert_int_equal(r.exit_status, 1);
  assert_true(r.output.find("royale lists no camera") != std::string::npos);
  assert_true(r.output.find("--camera-replay") != std::string::npos);
  // A simulated camera's path is no choice on the robot.
  r = run_fsw_app({"--hal", "real", "--camera", "raw", "--tasks", "camera", "--duration", "1"});
  assert_int_equal(r.exit_status, 2);
  assert_true(r.output.find("simulated camera's path") != std::string::npos);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s FSW_APP\n", argv[0]);
    return 2;
  }
  g_program = argv[1];
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_usb_faults_need_the_usb_path),
      cmocka_unit_test(test_robot_without_a_camera_says_so),
      cmocka_unit_test(test_robot_royale_without_a_camera_says_so),
      cmocka_unit_test(test_perch_through_the_usb_driver),
      cmocka_unit_test(test_perch_rides_out_an_unplug_and_a_stall),
      cmocka_unit_test(test_perch_through_royale),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
