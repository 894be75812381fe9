// Node 2's handrails stand on 45 deg corner panels: against the wall that
// fills most views they stand at no handrail's height, so they are found
// when verified on the surface around them (own_surface_min_tilt_deg), and
// hardly at all without it. Nothing is found in the views with no handrail
// either way.
#include "module_views.hpp"

namespace {

using moduleviews::Finds;

Finds detect_node2(const sim_hal::Scenario& sc, float own_surface_min_tilt_deg) {
  estimator::DetectorConfig cfg;
  cfg.own_surface_min_tilt_deg = own_surface_min_tilt_deg;
  return moduleviews::detect_views(sc, cfg);
}

void test_corner_panel_rails_are_found_on_their_own_surface(void**) {
  const sim_hal::Scenario sc = moduleviews::load_views("node2-views.json");
  const Finds on = detect_node2(sc, estimator::DetectorConfig{}.own_surface_min_tilt_deg);
  const Finds off = detect_node2(sc, 90.0f);
  print_message(
      "node2-views, %d frames with a rail: found %d (%d elsewhere) on their own surface, "
      "%d (%d) on the searched wall alone; %d of %d empty views with a find / %d\n",
      on.rail_frames, on.right, on.wrong, off.right, off.wrong, on.false_finds, on.empty_frames,
      off.false_finds);
  assert_true(on.empty_frames >= 12);
  assert_int_equal(on.false_finds, 0);
  assert_int_equal(off.false_finds, 0);
  // Measured: 60 against 17 (of 89).
  assert_true(on.right >= 2 * off.right + 10);
  assert_true(on.wrong <= off.wrong + 3);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_corner_panel_rails_are_found_on_their_own_surface),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
