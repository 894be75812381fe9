// hreval's statistics (tools/src/eval_metrics.cpp): the nearest-rank
// percentile that the 95th-percentile target is read with, and the
// median beside it; which handrail a detection is scored against when
// several are in view.
#include <cmath>

#include "cmocka_cpp.hpp"
#include "estimator/handrail_pose.hpp"
#include "eval_metrics.hpp"

namespace {

tools::Stats one_to(int n, bool descending) {
  tools::Stats s;
  for (int k = 1; k <= n; ++k) s.add(descending ? n + 1 - k : k);
  return s;
}

void test_percentile_is_the_nearest_rank(void**) {
  for (bool descending : {false, true}) {
    const tools::Stats s = one_to(20, descending);
    // The smallest value with at least p % of the values at or below it.
    assert_float_equal(s.percentile(95.0), 19.0, 0.0);
    assert_float_equal(s.percentile(96.0), 20.0, 0.0);
    assert_float_equal(s.percentile(50.0), 10.0, 0.0);
    assert_float_equal(s.percentile(5.0), 1.0, 0.0);
    assert_float_equal(s.percentile(100.0), 20.0, 0.0);
    // The rank is clamped to the values held.
    assert_float_equal(s.percentile(0.0), 1.0, 0.0);
    assert_float_equal(s.percentile(-3.0), 1.0, 0.0);
    assert_float_equal(s.percentile(250.0), 20.0, 0.0);
    // The upper median of an even count.
    assert_float_equal(s.median(), 11.0, 0.0);
    // The values stay as added.
    assert_float_equal(s.values.front(), descending ? 20.0 : 1.0, 0.0);
  }
  tools::Stats single;
  single.add(4.5);
  assert_float_equal(single.percentile(95.0), 4.5, 0.0);
  assert_true(std::isnan(tools::Stats{}.percentile(95.0)));
  assert_true(std::isnan(tools::Stats{}.median()));
}

// A handrail in the camera frame on a wall facing the camera: centre,
// direction in the image, the whole bar in view.
sim_hal::HandrailTruth rail(const Eigen::Vector3d& center, const Eigen::Vector3d& axis) {
  sim_hal::HandrailTruth h;
  h.center_cam = center;
  h.visible_center_cam = center;
  h.axis_cam = axis.normalized();
  h.normal_cam = Eigen::Vector3d(0, 0, -1);
  h.ends_cam[0] = center - 0.25 * h.axis_cam;
  h.ends_cam[1] = center + 0.25 * h.axis_cam;
  h.length_m = 0.5;
  h.visible_fraction = 1.0;
  h.end_in_view[0] = h.end_in_view[1] = true;
  return h;
}

estimator::HandrailDetection found_at(const sim_hal::HandrailTruth& h, double offset_m) {
  estimator::HandrailDetection d;
  d.status = estimator::DetectStatus::kFound;
  d.state = estimator::HandrailState::kBothEnds;
  d.p_cam_center = (h.center_cam + Eigen::Vector3d(offset_m, 0, 0)).cast<float>();
  d.R_cam_handrail =
      estimator::handrail_frame(h.normal_cam.cast<float>(), h.axis_cam.cast<float>());
  d.beam_length_m = 0.5f;
  return d;
}

// Three handrails at 0.8 m: the target and one parallel to it 12 cm
// beside (both along the image's y, the gripper's angle), and one across.
void test_a_detection_is_scored_against_the_parallel_handrail_it_found(void**) {
  sim_hal::FrameTruth truth;
  truth.handrails = {rail({0.0, 0.0, 0.8}, {0, 1, 0}), rail({0.12, 0.0, 0.8}, {0, 1, 0}),
                     rail({0.0, 0.2, 0.8}, {1, 0, 0})};
  const int target = tools::target_handrail(truth, 0.0);
  assert_int_equal(target, 0);
  // One frame tallied as hreval does: the detection scored against the
  // handrail scored_target picks, for both the target and the in-reach one.
  const auto tally = [&](const estimator::HandrailDetection& d) {
    tools::Tally t;
    t.add(d, truth, tools::scored_target(d, truth, 0.0, target, false),
          tools::scored_target(d, truth, 0.0, target, true));
    return t;
  };
  // The parallel one found: scored against it, correct, no false frame.
  const estimator::HandrailDetection parallel = found_at(truth.handrails[1], 0.003);
  assert_int_equal(tools::scored_target(parallel, truth, 0.0, target, false), 1);
  const tools::Tally t = tally(parallel);
  assert_int_equal(t.correct, 1);
  assert_int_equal(t.reach_correct, 1);
  assert_int_equal(t.false_found, 0);
  // The one across the gripper found: the target stays, the frame is false.
  const estimator::HandrailDetection across = found_at(truth.handrails[2], 0.0);
  assert_int_equal(tools::scored_target(across, truth, 0.0, target, false), 0);
  const tools::Tally f = tally(across);
  assert_int_equal(f.correct, 0);
  assert_int_equal(f.false_found, 1);
  // Between the two (6 cm from each): neither; nothing found: the target.
  assert_int_equal(
      tools::scored_target(found_at(truth.handrails[0], 0.06), truth, 0.0, target, false), 0);
  estimator::HandrailDetection none;
  none.status = estimator::DetectStatus::kNoLine;
  assert_int_equal(tools::scored_target(none, truth, 0.0, target, false), 0);
  // However little of the parallel one shows (the image's edge cuts it),
  // finding it is finding a handrail; out of reach (its visible part 1.9 m
  // away), it is not one in reach.
  truth.handrails[1].visible_fraction = 0.1;
  assert_int_equal(tools::scored_target(parallel, truth, 0.0, target, false), 1);
  assert_int_equal(tools::scored_target(parallel, truth, 0.0, target, true), 1);
  truth.handrails[1].visible_center_cam = Eigen::Vector3d(0.12, 0.0, 1.9);
  assert_int_equal(tools::scored_target(parallel, truth, 0.0, target, false), 1);
  assert_int_equal(tools::scored_target(parallel, truth, 0.0, target, true), 0);
  // Two it matches (the target and one 6 cm beside it, the detection 3.5
  // cm from the first): the nearer.
  sim_hal::FrameTruth two;
  two.handrails = {rail({0.0, 0.0, 0.8}, {0, 1, 0}), rail({0.06, 0.0, 0.8}, {0, 1, 0})};
  const estimator::HandrailDetection between = found_at(two.handrails[0], 0.035);
  assert_int_equal(tools::scored_target(between, two, 0.0, 0, false), 1);
  assert_int_equal(tools::scored_target(found_at(two.handrails[0], 0.02), two, 0.0, 0, false), 0);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_percentile_is_the_nearest_rank),
      cmocka_unit_test(test_a_detection_is_scored_against_the_parallel_handrail_it_found),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
