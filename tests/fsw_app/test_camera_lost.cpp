// A camera that stops delivering mid-approach, end to end: the fsw_app
// program on the simulated HAL, its in-process camera swallowed by the
// run's camera cut (--fault camera-silent / camera-lost). A gap of 2 s is
// held through (the perch manager's camera rule) and the perch resumes
// and succeeds; frames gone for good end the perch CAMERA_LOST with the
// arm folded to stow. The summary reports what the manager saw.
//   argv[1]: the fsw_app program
#include <cmath>
#include <cstdio>

#include "cmocka_cpp.hpp"
#include "hil_perch.hpp"

namespace {

using namespace hil_perch;

double watch(const Outcome& o, const char* key) {
  return nested(o, {"camera", "watch", key});
}

std::string watch_status(const Outcome& o) {
  return o.text_at({"camera", "watch", "status"});
}

// 2 s without a frame, 1 s into the approach: held (frames late for about
// 1.4 s of it), then on to a perch within 1 cm; no HANDRAIL_LOST although
// the gap outlasts handrail_lost_ms.
void test_camera_silent_two_seconds_holds_then_perches(void**) {
  const Outcome o = run_expecting(
      "approach-iss", {"--seed", "7", "--fault", "camera-silent@1"},
      [](const Outcome& r) { return perched_within_1cm(r) && watch(r, "late_spells") >= 1; });
  std::printf("  camera watch: %.0f late spells, late %.0f ms, longest gap %.0f ms, %s\n",
              watch(o, "late_spells"), watch(o, "late_ms"), watch(o, "longest_frame_gap_ms"),
              watch_status(o).c_str());
  assert_true(o.flag("perched"));
  assert_true(o.flag("success"));
  assert_string_equal(o.text("fault").c_str(), "NONE");
  assert_true(watch(o, "late_spells") >= 1);
  // The cut is 2 s: the gap between frames spans it, and the manager held
  // for the part past its bound (3 frame periods, 0.6 s).
  assert_true(watch(o, "longest_frame_gap_ms") >= 1900.0);
  assert_true(watch(o, "late_ms") >= 1000.0);
  assert_string_equal(watch_status(o).c_str(), "STREAMING");
}

// No frame from 1 s into the approach on: held, then CAMERA_LOST
// camera_lost_ms (3 s) after the frames went late, the arm folded to its
// stow posture (90, 0 deg in fsw_app.json); no perch, exit status 1.
void test_camera_lost_for_good_folds_the_arm(void**) {
  const Outcome o =
      run_expecting("approach-iss", {"--seed", "8", "--fault", "camera-lost@1"},
                    [](const Outcome& r) { return r.text("fault") == "CAMERA_LOST"; });
  std::printf("  arm %.3f / %.3f rad at the end; camera %s\n", o.number("arm_tilt_rad"),
              o.number("arm_pan_rad"), watch_status(o).c_str());
  assert_string_equal(o.text("fault").c_str(), "CAMERA_LOST");
  assert_string_equal(o.text("arm_state").c_str(), "FAULT");
  assert_false(o.flag("perched"));
  assert_int_equal(o.exit_status, 1);
  assert_true(std::fabs(o.number("arm_tilt_rad") - M_PI / 2) < 0.05);
  assert_true(std::fabs(o.number("arm_pan_rad")) < 0.05);
  assert_string_equal(watch_status(o).c_str(), "LATE");
  assert_true(watch(o, "late_spells") >= 1);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s FSW_APP\n", argv[0]);
    return 2;
  }
  hil_perch::init(argv[1]);
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_camera_silent_two_seconds_holds_then_perches),
      cmocka_unit_test(test_camera_lost_for_good_folds_the_arm),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
