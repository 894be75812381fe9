// hreval's statistics (tools/src/eval_metrics.cpp): the nearest-rank
// percentile that issue #17's 95th-percentile figure is read with, and the
// median beside it.
#include <cmath>

#include "cmocka_cpp.hpp"
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

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_percentile_is_the_nearest_rank),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
