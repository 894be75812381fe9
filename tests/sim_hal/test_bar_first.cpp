// The bar-first search (DetectorConfig::bar_first) on two real modules no
// constant of it was chosen with: Node 3's rails stand on flat panels and
// blocks at 6.1 to 6.5 cm, the Cupola's on window frames tilted from the
// walls around them. The default search, which reads the bar's height
// against the dominant plane and the surfaces in view, finds under half of
// them; the bar-first search, which takes the bar's runs as candidates and
// judges each line on the surface around it, finds most. In the views with
// no rail in them the default finds nothing; the bar first, one thing in
// one of Node 3's 13 (not yet 0). Node 1 is the module the bar-first end
// walk was mended on: its rails on 45 deg corner panels, seen at a slant,
// collect the panel beside them as line inliers, and where those set the
// bar's extent the end walk read 5 to 10 cm of "ramp" past the front.
#include "module_views.hpp"

namespace {

using moduleviews::Finds;

void expect_more_found_bar_first(const char* views, int measured_default, int measured_bar_first,
                                 int measured_false_bar_first) {
  const sim_hal::Scenario sc = moduleviews::load_views(views);
  estimator::DetectorConfig bar_first;
  bar_first.bar_first = true;
  const Finds base = moduleviews::detect_views(sc, estimator::DetectorConfig{});
  const Finds first = moduleviews::detect_views(sc, bar_first);
  print_message(
      "%s, %d frames with a rail: bar first %d (%d elsewhere), default %d (%d); "
      "%d and %d of %d empty views with a find (measured %d and %d)\n",
      views, first.rail_frames, first.right, first.wrong, base.right, base.wrong, first.false_finds,
      base.false_finds, first.empty_frames, measured_bar_first, measured_default);
  assert_true(first.empty_frames >= 12);
  assert_true(first.false_finds <= measured_false_bar_first);
  assert_int_equal(base.false_finds, 0);
  // A few frames' margin either way on the measured counts.
  assert_true(first.right >= measured_bar_first - 4);
  assert_true(base.right <= measured_default + 4);
  assert_true(first.wrong <= base.wrong + 4);
}

void test_node3_rails_are_found_bar_first(void**) {
  expect_more_found_bar_first("node3-views.json", 37, 83, 1);
}

void test_cupola_rails_are_found_bar_first(void**) {
  expect_more_found_bar_first("cupola-views.json", 41, 67, 0);
}

void test_node1_rails_on_corner_panels_are_found_bar_first(void**) {
  expect_more_found_bar_first("node1-views.json", 62, 83, 0);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_node3_rails_are_found_bar_first),
      cmocka_unit_test(test_cupola_rails_are_found_bar_first),
      cmocka_unit_test(test_node1_rails_on_corner_panels_are_found_bar_first),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
