// hrcompare on real LCM log files written here: agreeing logs pass, a
// position or state difference fails, a file that is not a log is a usage
// error naming it.
//   argv[1]: the hrcompare program
#include <unistd.h>

#include <lcm/lcm-cpp.hpp>

#include <cstdio>
#include <string>
#include <vector>

#include "child_process.hpp"
#include "cmocka_cpp.hpp"
#include "hrp/handrail_estimate_t.hpp"

namespace {

std::string g_program;

std::string temp_path(const char* name) {
  return "/tmp/hrcompare_" + std::to_string(getpid()) + "_" + name;
}

hrp::handrail_estimate_t estimate(long frame_id, int state, double x_m) {
  hrp::handrail_estimate_t m{};
  m.frame_id = frame_id;
  m.state = static_cast<std::int8_t>(state);
  m.T_cam_handrail.position_m[0] = x_m;
  m.T_cam_handrail.position_m[2] = 0.6;
  m.T_cam_handrail.quat_wxyz[0] = 1.0;
  return m;
}

// A log of `count` frames looping over a folder of `folder` frames; the
// frame `odd_one` (if >= 0) gets the given state and x.
std::string write_log(const char* name, int count, int odd_one, int odd_state, double odd_x_m) {
  const std::string path = temp_path(name);
  lcm::LogFile log(path, "w");
  assert_true(log.good());
  for (int k = 0; k < count; ++k) {
    const bool odd = k == odd_one;
    hrp::handrail_estimate_t m = estimate(k, odd ? odd_state : 1, odd ? odd_x_m : 0.01 * k);
    std::vector<std::uint8_t> buf(static_cast<std::size_t>(m.getEncodedSize()));
    assert_true(m.encode(buf.data(), 0, static_cast<int>(buf.size())) > 0);
    lcm::LogEvent e{};
    e.eventnum = k;
    e.timestamp = 1000 * k;
    e.channel = "HANDRAIL_ESTIMATE";
    e.datalen = static_cast<std::int32_t>(buf.size());
    e.data = buf.data();
    assert_int_equal(log.writeEvent(&e), 0);
  }
  return path;
}

int run(std::vector<std::string> args) {
  return testing_support::run_to_exit(g_program, std::move(args));
}

void test_agreeing_logs_pass(void**) {
  const std::string a = write_log("a1", 12, -1, 0, 0.0), b = write_log("b1", 12, -1, 0, 0.0);
  assert_int_equal(run({a, b, "--min-frames", "12"}), 0);
  // Fewer frames in both logs than required: a failure, not a pass.
  assert_int_equal(run({a, b, "--min-frames", "13"}), 1);
  std::remove(a.c_str());
  std::remove(b.c_str());
}

void test_a_moved_handrail_fails(void**) {
  const std::string a = write_log("a2", 12, -1, 0, 0.0);
  const std::string b = write_log("b2", 12, 5, 1, 0.05 + 0.002);  // 2 mm off at frame 5
  assert_int_equal(run({a, b}), 1);
  assert_int_equal(run({a, b, "--tol-mm", "3"}), 0);
  std::remove(a.c_str());
  std::remove(b.c_str());
}

void test_a_different_state_fails(void**) {
  const std::string a = write_log("a3", 12, -1, 0, 0.0);
  const std::string b = write_log("b3", 12, 7, 0, 0.0);  // NH where A saw the bar
  assert_int_equal(run({a, b}), 1);
  std::remove(a.c_str());
  std::remove(b.c_str());
}

void test_looped_replays_compare_by_recorded_frame(void**) {
  // A replays 24 ids over a folder of 12; B only the first pass. Modulo 12
  // every recorded frame is in both.
  const std::string a = write_log("a4", 24, -1, 0, 0.0), b = write_log("b4", 12, -1, 0, 0.0);
  assert_int_equal(run({a, b, "--frames", "12", "--min-frames", "12"}), 0);
  std::remove(a.c_str());
  std::remove(b.c_str());
}

void test_bad_input_is_a_usage_error(void**) {
  const std::string junk = temp_path("junk");
  FILE* f = std::fopen(junk.c_str(), "w");
  assert_non_null(f);
  std::fputs("not an LCM log\n", f);
  std::fclose(f);
  const std::string a = write_log("a5", 12, -1, 0, 0.0);
  assert_int_equal(run({a, "/nonexistent/log.lcm"}), 2);
  assert_int_equal(run({a}), 2);
  assert_int_equal(run({a, a, "--tol-mm", "lots"}), 2);
  // A file that is not a log holds no estimates: nothing to compare.
  assert_int_equal(run({a, junk}), 1);
  std::remove(a.c_str());
  std::remove(junk.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s HRCOMPARE\n", argv[0]);
    return 2;
  }
  g_program = argv[1];
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_agreeing_logs_pass),
      cmocka_unit_test(test_a_moved_handrail_fails),
      cmocka_unit_test(test_a_different_state_fails),
      cmocka_unit_test(test_looped_replays_compare_by_recorded_frame),
      cmocka_unit_test(test_bad_input_is_a_usage_error),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
