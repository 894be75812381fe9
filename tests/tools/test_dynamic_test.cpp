// dynamic_test, the paper's dynamic experiment in the simulator, on the
// paper's round bar: by default the detector looks for the geometry of
// the scenario's handrail, so the filter takes handrail updates and holds
// the robot to the bar within millimetres; told to look for the ISS bar
// there it finds no end and takes none. And its bad options.
//   argv[1]: the dynamic_test program
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "child_process.hpp"
#include "cmocka_cpp.hpp"
#include "test_data.hpp"

namespace {

std::string g_program;
std::string g_dir;

using Result = testing_support::RunOutput;

// Runs 10 s of the experiment on approach-round; the summary's text.
std::string run_round(const std::string& name, std::vector<std::string> extra) {
  std::vector<std::string> args = {
      "--out",      g_dir + "/" + name,
      "--scenario", testing_support::source_path("sim_hal/scenarios/approach-round.json"),
      "--config",   testing_support::source_path("fsw_app/config/fsw_app.json"),
      "--duration", "10"};
  args.insert(args.end(), extra.begin(), extra.end());
  const Result r = testing_support::run_capturing(g_program, args, g_dir + "/" + name + ".txt");
  if (r.exit_status != 0) fail_msg("dynamic_test exited %d:\n%s", r.exit_status, r.out.c_str());
  return testing_support::read_text(g_dir + "/" + name + "/summary.json");
}

double number_after(const std::string& text, const std::string& key) {
  const std::size_t at = text.find(key);
  if (at == std::string::npos) fail_msg("no \"%s\" in:\n%s", key.c_str(), text.c_str());
  return std::strtod(text.c_str() + at + key.size(), nullptr);
}

void test_round_bar_is_looked_for_as_round(void**) {
  const std::string s = run_round("round", {});
  assert_true(s.find("\"handrail\": \"round\"") != std::string::npos);
  const double accepted = number_after(s, "\"handrail_accepted\": ");
  std::printf("round bar, round geometry: %.0f handrail updates\n", accepted);
  assert_true(accepted >= 20.0);  // a frame every 0.2 s for 10 s after 5 s settling
  const std::string iss = run_round("iss", {"--handrail", "iss"});
  assert_true(iss.find("\"handrail\": \"iss\"") != std::string::npos);
  const double iss_accepted = number_after(iss, "\"handrail_accepted\": ");
  std::printf("round bar, ISS geometry: %.0f handrail updates\n", iss_accepted);
  assert_true(iss_accepted < accepted);
}

void test_bad_handrail_is_refused(void**) {
  const Result r =
      testing_support::run_capturing(g_program, {"--handrail", "oval"}, g_dir + "/bad.txt");
  assert_int_equal(r.exit_status, 2);
  assert_true(r.out.find("--handrail iss|round") != std::string::npos);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s DYNAMIC_TEST\n", argv[0]);
    return 2;
  }
  g_program = argv[1];
  const testing_support::ScratchDir scratch("hrp_dynamic_test");
  if (scratch.path().empty()) return 1;
  g_dir = scratch.path();
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_round_bar_is_looked_for_as_round),
      cmocka_unit_test(test_bad_handrail_is_refused),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
