// The ISS handrail lengths the detector knows (handrail_types): a bar seen
// end to end matched to one by its length, the shortest partial bar, and
// the mount and type settings refused by name (validate).
#include <cmath>

#include "cmocka_cpp.hpp"
#include "estimator/config.hpp"
#include "estimator/handrail_types.hpp"

using namespace estimator;

namespace {

void test_iss_lengths_are_matched_by_ratio(void**) {
  const DetectorConfig cfg;  // the station's four handrails and the module rail
  struct Case {
    float beam_m;
    const char* type;  // nullptr: no handrail has that length
  } cases[] = {{0.20f, "8.5 in"}, {0.215f, "8.5 in"},     {0.53f, "21.5 in"}, {0.48f, "21.5 in"},
               {0.76f, "30 in"},  {0.98f, "module rail"}, {1.06f, "41.5 in"}, {0.33f, nullptr},
               {0.10f, nullptr},  {1.40f, nullptr}};
  for (const Case& c : cases) {
    const int k = match_handrail_type(cfg, c.beam_m);
    if (c.type == nullptr) {
      assert_int_equal(k, -1);
      assert_false(beam_length_matches(cfg, c.beam_m));
    } else {
      assert_true(k >= 0);
      assert_string_equal(cfg.handrail_types[k].name, c.type);
      assert_true(beam_length_matches(cfg, c.beam_m));
    }
  }
  assert_near(longest_handrail_m(cfg), 1.040f, 1e-6f);
}

void test_one_configured_length_without_types(void**) {
  DetectorConfig cfg;
  cfg.handrail_type_count = 0;
  cfg.handrail = iss_handrail(0.3f);
  assert_int_equal(match_handrail_type(cfg, 0.3f), -1);
  assert_true(beam_length_matches(cfg, 0.3f));
  assert_false(beam_length_matches(cfg, 0.53f));
  assert_near(longest_handrail_m(cfg), 0.3f, 1e-6f);
}

// A partial bar may be as short as 35 % of the shortest known handrail,
// but never longer than the 8 cm clutter floor requires.
void test_the_shortest_partial_bar(void**) {
  estimator::DetectorConfig cfg;  // the ISS types, the shortest 8.5 in
  float shortest = INFINITY;
  for (std::uint32_t k = 0; k < cfg.handrail_type_count; ++k) {
    shortest = std::fmin(shortest, cfg.handrail_types[k].bar_length_m);
  }
  assert_true(shortest < 0.21f);
  assert_float_equal(estimator::shortest_partial_bar_m(cfg), 0.35f * shortest, 1e-6f);
  cfg.min_visible_fraction = 1.0f;
  assert_float_equal(estimator::shortest_partial_bar_m(cfg), cfg.min_visible_length_m, 1e-6f);
  estimator::DetectorConfig one_length;  // the paper's round bar alone
  one_length.handrail_type_count = 0;
  one_length.handrail.bar_length_m = 0.55f;
  assert_float_equal(estimator::shortest_partial_bar_m(one_length), 0.08f, 1e-6f);
  one_length.handrail.bar_length_m = 0.15f;
  assert_float_equal(estimator::shortest_partial_bar_m(one_length), 0.0525f, 1e-6f);
}

void test_bad_mount_and_type_settings_are_named(void**) {
  DetectorConfig cfg;
  cfg.max_mount_hypotheses = 0;
  assert_string_equal(validate(cfg), "max_mount_hypotheses");
  cfg = DetectorConfig{};
  cfg.max_mount_hypotheses = kMaxMountHypotheses + 1;
  assert_string_equal(validate(cfg), "max_mount_hypotheses");
  cfg = DetectorConfig{};
  cfg.mount_search_m = -0.01f;
  assert_string_equal(validate(cfg), "mount_search_m");
  cfg = DetectorConfig{};
  cfg.mount_bay_max_m = 0.5f;  // beyond the histogram's span
  assert_string_equal(validate(cfg), "mount_bay_max_m");
  cfg = DetectorConfig{};
  cfg.mount_bay_min_m = 0.3f;
  cfg.mount_bay_max_m = 0.2f;
  assert_string_equal(validate(cfg), "mount_bay_max_m");
  cfg = DetectorConfig{};
  cfg.mount_bay_min_m = cfg.mount_bay_max_m = -0.1f;
  assert_string_equal(validate(cfg), "mount_bay_min_m");
  cfg = DetectorConfig{};
  cfg.mount_beside_max_m = cfg.mount_beside_min_m;
  assert_string_equal(validate(cfg), "mount_beside_max_m");
  cfg = DetectorConfig{};
  cfg.mount_beside_min_fraction = 1.5f;
  assert_string_equal(validate(cfg), "mount_beside_min_fraction");
  cfg = DetectorConfig{};
  cfg.end_drop_max_m = 0.0f;
  assert_string_equal(validate(cfg), "end_drop_max_m");
  cfg = DetectorConfig{};
  cfg.min_visible_fraction = 0.0f;
  assert_string_equal(validate(cfg), "min_visible_fraction");
  cfg.min_visible_fraction = 1.5f;
  assert_string_equal(validate(cfg), "min_visible_fraction");
  cfg = DetectorConfig{};
  cfg.min_visible_length_m = NAN;
  assert_string_equal(validate(cfg), "min_visible_length_m");
  cfg = DetectorConfig{};
  cfg.handrail_types[1].bar_length_m = NAN;
  assert_string_equal(validate(cfg), "handrail_types");
  cfg = DetectorConfig{};
  cfg.handrail_type_count = kMaxHandrailTypes + 1;
  assert_string_equal(validate(cfg), "handrail_types");
  cfg = DetectorConfig{};
  cfg.front_peak_mounts = kMaxMountHypotheses - cfg.max_mount_hypotheses_bay + 1;
  assert_string_equal(validate(cfg), "front_peak_mounts");
  cfg = DetectorConfig{};
  cfg.max_mount_hypotheses_bay = cfg.max_mount_hypotheses - 1;
  assert_string_equal(validate(cfg), "max_mount_hypotheses_bay");
  cfg.max_mount_hypotheses_bay = kMaxMountHypotheses + 1;
  assert_string_equal(validate(cfg), "max_mount_hypotheses_bay");
  cfg = DetectorConfig{};
  cfg.profile_min_obliquity_deg = 95.0f;
  assert_string_equal(validate(cfg), "profile_min_obliquity_deg");
  cfg = DetectorConfig{};
  cfg.profile_min_spread_m = NAN;
  assert_string_equal(validate(cfg), "profile_min_spread_m");
  cfg = DetectorConfig{};
  cfg.line_max_turn_deg = 0.0f;
  assert_string_equal(validate(cfg), "line_max_turn_deg");
  cfg = DetectorConfig{};
  cfg.clearance_low_m = 0.04f;  // above the band's top
  assert_string_equal(validate(cfg), "clearance_low_m");
  cfg = DetectorConfig{};
  cfg.clearance_high_m = 0.05f;  // into the gap window: the bar's own pixels
  assert_string_equal(validate(cfg), "clearance_high_m");
  cfg = DetectorConfig{};
  cfg.clearance_max_solid_fraction = 0.0f;
  assert_string_equal(validate(cfg), "clearance_max_solid_fraction");
  cfg = DetectorConfig{};
  cfg.max_find_range_m = 2.5f;  // past the points used: nothing to find there
  assert_string_equal(validate(cfg), "max_find_range_m");
  cfg = DetectorConfig{};
  cfg.max_find_range_m = NAN;
  assert_string_equal(validate(cfg), "max_find_range_m");
  assert_null(validate(DetectorConfig{}));
}

}  // namespace

int main() {
  const CMUnitTest tests[] = {
      cmocka_unit_test(test_iss_lengths_are_matched_by_ratio),
      cmocka_unit_test(test_one_configured_length_without_types),
      cmocka_unit_test(test_the_shortest_partial_bar),
      cmocka_unit_test(test_bad_mount_and_type_settings_are_named),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
