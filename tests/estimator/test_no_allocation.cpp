// Proof that the detector allocates nothing while it processes frames:
// every operator new and (outside AddressSanitizer) every malloc on the
// test's thread is counted while armed, over hundreds of frames.
#include <vector>

#include "allocation_counter.hpp"
#include "cmocka_cpp.hpp"
#include "estimator/handrail_detector.hpp"
#include "recorded_frames.hpp"
#include "synthetic_cloud.hpp"

using namespace estimator;

namespace {

void test_counter_counts(void**) {
  alloc_counter::arm();
  std::vector<int>* v = new std::vector<int>(10);
  const long n = alloc_counter::disarm();
  delete v;
  assert_true(n >= 2);  // the vector object and its storage
}

void test_no_allocation_over_hundreds_of_frames(void**) {
  // Real recorded frames (224 x 171) and synthetic ones (160 x 120), with a
  // handrail, without one, and invalid: every path through the detector.
  std::vector<std::vector<CloudPoint>> frames;
  std::vector<OrganizedCloud> clouds;
  for (const char* name : {"table2-iss-1.pcd", "table2-round-2.pcd", "clutter-only-0.pcd"}) {
    testing_support::RecordedCloud recorded;
    std::string error;
    assert_true(testing_support::load_recorded_cloud(name, &recorded, &error));
    frames.push_back(std::move(recorded.points));
    clouds.push_back(recorded.cloud);
  }
  testing_support::SyntheticScene s;
  s.cylinders.push_back(testing_support::vertical_bar(0.6, 0.0825, 0.3));
  s.noise_m = 0.002;
  frames.emplace_back();
  clouds.push_back(testing_support::render(s, &frames.back()));
  frames.emplace_back(160 * 120, CloudPoint{0, 0, 0, 0, 0, 0});
  clouds.push_back({0, 0, 160, 120, nullptr});
  for (std::size_t k = 0; k < clouds.size(); ++k) clouds[k].points = frames[k].data();

  // One detector per handrail kind, both built before counting starts.
  DetectorConfig iss_cfg;
  iss_cfg.budget_us = 1000000;  // exercise the budget checks too
  iss_cfg.gripper_angle_rad = 1.5707963f;
  DetectorConfig round_cfg = iss_cfg;
  round_cfg.handrail = paper_round_handrail(0.55f);
  round_cfg.plane_faces_normal = true;  // the optional wall normal allocates nothing either
  DetectorConfig synthetic_cfg = iss_cfg;
  synthetic_cfg.handrail = paper_round_handrail(0.3f);
  synthetic_cfg.gripper_angle_rad = 0.0f;
  DetectorConfig bar_first_cfg = iss_cfg;
  bar_first_cfg.bar_first = true;  // the bar-first search and its own-surface fits
  HandrailDetector iss(iss_cfg), round(round_cfg), synthetic(synthetic_cfg),
      bar_first(bar_first_cfg);
  iss.set_line_trace(true);  // the diagnostics' line trace allocates nothing either
  HandrailDetector* detector_for[] = {&iss, &round, &iss, &synthetic, &synthetic};
  int found_bar_first = 0;
  int found = 0;
  alloc_counter::arm();
  for (int n = 0; n < 300; ++n) {
    OrganizedCloud c = clouds[static_cast<std::size_t>(n) % clouds.size()];
    c.frame_id = static_cast<std::uint64_t>(n);  // new random numbers each frame
    const Method m = n % 7 == 3 ? Method::kBasic : Method::kProposed;
    found += detector_for[static_cast<std::size_t>(n) % clouds.size()]->detect(c, m).status ==
             DetectStatus::kFound;
    // Every frame again bar first (the real ISS frame and the clutter).
    found_bar_first += bar_first.detect(c).status == DetectStatus::kFound;
  }
  const long allocations = alloc_counter::disarm();
  if (allocations != 0) print_error("%ld allocations while processing frames\n", allocations);
  assert_int_equal(allocations, 0);
  assert_true(found > 100);  // the frames exercised the full pipeline
  assert_true(found_bar_first > 50);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_counter_counts),
      cmocka_unit_test(test_no_allocation_over_hundreds_of_frames),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
