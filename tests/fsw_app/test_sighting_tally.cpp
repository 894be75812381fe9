// The run summary's sightings (fsw_app/sighting_tally.hpp): estimates
// delivered as LCM bytes are counted by state; BE lengths give the range
// and the ISS type each matched (or none); a message that does not decode
// or fails the input checks is counted as refused and changes nothing else.
#include <cmath>
#include <string>
#include <vector>

#include "cmocka_cpp.hpp"
#include "estimator/config.hpp"
#include "fsw_app/input_gates.hpp"
#include "fsw_app/sighting_tally.hpp"
#include "hrp/handrail_estimate_t.hpp"

namespace {

std::vector<std::uint8_t> encoded(std::int8_t state, double length_m) {
  hrp::handrail_estimate_t m{};
  m.utime = 1;
  m.frame_id = 1;
  m.capture_utime = 1;
  m.state = state;
  m.bar_length_m = length_m;
  for (hrp::pose_t* p : {&m.T_cam_handrail, &m.T_body_handrail, &m.T_body_target, &m.T_world_target,
                         &m.T_world_handrail}) {
    p->quat_wxyz[0] = 1.0;
  }
  if (state != hrp::handrail_estimate_t::STATE_NH) m.T_cam_handrail.position_m[2] = 0.8;
  m.num_ends = state == hrp::handrail_estimate_t::STATE_BE ? 2 : 0;
  std::vector<std::uint8_t> buf(static_cast<std::size_t>(m.getEncodedSize()));
  assert_true(m.encode(buf.data(), 0, static_cast<int>(buf.size())) > 0);
  return buf;
}

void deliver(fsw_app::SightingTally& t, const std::vector<std::uint8_t>& bytes) {
  t.deliver(bytes.data(), static_cast<std::uint32_t>(bytes.size()), fsw_app::kNoReceiverClock);
}

void test_states_lengths_and_types_are_counted(void**) {
  const estimator::DetectorConfig cfg;  // the five ISS types
  fsw_app::SightingTally t(cfg);
  const fsw_app::SightingReport empty = t.report();
  assert_int_equal(empty.counts.by_state[1], 0);
  assert_int_equal(empty.type_count, 5);
  deliver(t, encoded(hrp::handrail_estimate_t::STATE_BE, 0.55));
  deliver(t, encoded(hrp::handrail_estimate_t::STATE_BE, 0.54));
  deliver(t, encoded(hrp::handrail_estimate_t::STATE_BE, 0.21));  // a short find: 8.5 in
  deliver(t, encoded(hrp::handrail_estimate_t::STATE_BE, 2.50));  // no ISS length
  deliver(t, encoded(hrp::handrail_estimate_t::STATE_OE, 0.0));
  deliver(t, encoded(hrp::handrail_estimate_t::STATE_NE, 0.0));
  deliver(t, encoded(hrp::handrail_estimate_t::STATE_NH, 0.0));
  std::vector<std::uint8_t> cut = encoded(hrp::handrail_estimate_t::STATE_BE, 0.55);
  cut.resize(cut.size() / 2);
  deliver(t, cut);
  deliver(t, encoded(9, 0.55));  // a state that does not exist: refused by the input checks
  const fsw_app::SightingReport r = t.report();
  assert_int_equal(r.counts.by_state[0], 1);
  assert_int_equal(r.counts.by_state[1], 4);
  assert_int_equal(r.counts.by_state[2], 1);
  assert_int_equal(r.counts.by_state[3], 1);
  assert_int_equal(r.counts.rejected, 2);
  assert_float_equal(r.counts.be_length_min_m, 0.21, 1e-6);
  assert_float_equal(r.counts.be_length_max_m, 2.50, 1e-6);
  std::uint64_t named = 0;
  for (std::uint32_t k = 0; k < r.type_count; ++k) {
    const std::string name = r.type_names[k];
    if (name == "21.5 in") assert_int_equal(r.counts.be_by_type[k], 2);
    if (name == "8.5 in") assert_int_equal(r.counts.be_by_type[k], 1);
    named += r.counts.be_by_type[k];
  }
  assert_int_equal(named, 3);
  assert_int_equal(r.counts.be_by_type[estimator::kMaxHandrailTypes], 1);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_states_lengths_and_types_are_counted),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
