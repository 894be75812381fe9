// armctl, the built program, against simulated AX-12A servos on a pty:
// exit statuses (0 done, 1 the device failed, 2 usage), a silent servo,
// a servo error bit, arguments refused whole and by name before anything
// is sent, a bad --baud named, and a scan that finds each servo once.
//   argv[1]: the armctl program
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "child_process.hpp"
#include "cmocka_cpp.hpp"
#include "dynamixel/ax12.hpp"
#include "sim_hal/sim_servo_bus.hpp"

namespace ax12 = dynamixel::ax12;

namespace {

std::string g_program;

struct Run {
  int status = -1;
  std::string out;  // stdout and stderr together
  bool says(const std::string& text) const { return out.find(text) != std::string::npos; }
};

Run run(std::vector<std::string> args) {
  const std::string path = "/tmp/armctl_test_" + std::to_string(getpid()) + ".out";
  Run r;
  r.status = testing_support::wait_for_exit(
      testing_support::spawn_program(g_program, std::move(args), path));
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  r.out = ss.str();
  std::remove(path.c_str());
  return r;
}

// A wide reply margin: the simulated servos are a thread of this test on a
// host that may be loaded; the bus's own timing is tested elsewhere.
std::vector<std::string> on(const sim_hal::SimServoBus& sim, std::vector<std::string> words) {
  std::vector<std::string> args = {"--port", sim.path(), "--margin-us", "150000"};
  args.insert(args.end(), words.begin(), words.end());
  return args;
}

void expect(const Run& r, int status, const std::string& text) {
  if (r.status != status || !r.says(text)) {
    print_error("exit %d (expected %d), output:\n%s(expected to contain '%s')\n", r.status, status,
                r.out.c_str(), text.c_str());
    fail();
  }
}

struct Servos {
  sim_hal::SimServoBus sim;
  Servos() {
    std::string error;
    assert_true(sim.start(&error));
  }
  std::uint8_t table(std::uint8_t id, std::uint8_t address) {
    sim_hal::SimServo s;
    assert_true(sim.servo(id, &s));
    return s.table(address);
  }
  std::uint16_t table16(std::uint8_t id, std::uint8_t address) {
    sim_hal::SimServo s;
    assert_true(sim.servo(id, &s));
    return s.table16(address);
  }
};

void test_success_exits_0(void**) {
  Servos s;
  Run r = run(on(s.sim, {"torque", "1", "on"}));
  expect(r, 0, "OK");
  assert_int_equal(s.table(1, ax12::kTorqueEnable), 1);
  expect(run(on(s.sim, {"torque", "1", "off"})), 0, "OK");
  assert_int_equal(s.table(1, ax12::kTorqueEnable), 0);
  expect(run(on(s.sim, {"ping", "2"})), 0, "ID 2: OK");
  expect(run(on(s.sim, {"read", "1", "0", "2"})), 0, "0: 12");
  expect(run(on(s.sim, {"write", "1", "25", "1"})), 0, "OK");
  assert_int_equal(s.table(1, ax12::kLed), 1);
  expect(run(on(s.sim, {"move", "2", "10", "90"})), 0, "OK");
  assert_int_equal(s.table16(2, ax12::kGoalPosition), ax12::position_units(10.0 * M_PI / 180.0));
  expect(run(on(s.sim, {"move", "2", "-150.1"})), 0, "OK");
  assert_int_equal(s.table16(2, ax12::kGoalPosition), 0);
  expect(run(on(s.sim, {"recover", "2"})), 0, "OK");
}

void test_a_silent_servo_exits_1(void**) {
  Servos s;
  sim_hal::BusFaults silent;
  silent.no_reply = true;
  s.sim.set_faults(silent);
  for (const std::vector<std::string>& words : {std::vector<std::string>{"torque", "1", "on"},
                                                {"move", "1", "10"},
                                                {"write", "1", "25", "1"},
                                                {"recover", "1"},
                                                {"ping", "1"},
                                                {"read", "1", "36", "2"}}) {
    const Run r = run(on(s.sim, words));
    expect(r, 1, "TIMEOUT");
  }
  // Nothing answers a scan either.
  expect(run(on(s.sim, {"scan", "0", "3"})), 1, "0 servo(s) found");
}

void test_a_servo_error_bit_exits_1(void**) {
  Servos s;
  // A goal of 1024 is past the end stop: the servo answers with the
  // angle-limit bit, which is a failure of the command.
  expect(run(on(s.sim, {"write", "1", "30", "0", "4"})), 1, "ANGLE_LIMIT");
  // An overload that persists: recovery is refused.
  s.sim.force_error_bits(2, dynamixel::kErrorOverload);
  expect(run(on(s.sim, {"recover", "2"})), 1, "OVERLOAD");
  expect(run(on(s.sim, {"torque", "2", "on"})), 1, "OVERLOAD");
}

void test_arguments_are_refused_whole_and_by_name(void**) {
  Servos s;
  const std::uint16_t goal_before = s.table16(1, ax12::kGoalPosition);
  const std::uint64_t packets_before = s.sim.packets_handled();
  struct Case {
    std::vector<std::string> words;
    const char* names;  // what the message must name
  };
  const Case cases[] = {
      {{"move", "1", "nan"}, "DEGREES 'nan'"},
      {{"move", "1", "-nan"}, "DEGREES '-nan'"},
      {{"move", "1", "inf"}, "DEGREES 'inf'"},
      {{"move", "1", "1e999"}, "DEGREES '1e999'"},
      {{"move", "1", "12abc"}, "DEGREES '12abc'"},
      {{"move", "1", ""}, "DEGREES ''"},
      {{"move", "1", "150"}, "DEGREES '150'"},
      {{"move", "1", "-151"}, "DEGREES '-151'"},
      {{"move", "1", "10", "0"}, "DEG_S '0'"},
      {{"move", "1", "10", "-5"}, "DEG_S '-5'"},
      {{"move", "1", "10", "nan"}, "DEG_S 'nan'"},
      {{"move", "1", "10", "700"}, "DEG_S '700'"},
      {{"ping", "254"}, "ID '254'"},
      {{"ping", "-1"}, "ID '-1'"},
      {{"ping", "1.5"}, "ID '1.5'"},
      {{"ping", "0x1"}, "ID '0x1'"},
      {{"ping", "99999999999999999999"}, "ID '99999999999999999999'"},
      {{"ping", "1", "2"}, "argument '2'"},
      {{"torque", "1", "maybe"}, "state 'maybe'"},
      {{"torque", "one", "on"}, "ID 'one'"},
      {{"read", "1", "50", "1"}, "ADDRESS '50'"},
      {{"read", "1", "48", "3"}, "LENGTH '3'"},
      {{"read", "1", "0", "0"}, "LENGTH '0'"},
      {{"write", "1", "24", "256"}, "BYTE '256'"},
      {{"write", "1", "24", "1x"}, "BYTE '1x'"},
      {{"write", "1", "49", "1", "2"}, "BYTE '2'"},
      {{"scan", "5", "2"}, "LAST '2'"},
      {{"scan", "300"}, "FIRST '300'"},
      {{"gripper", "close", "0"}, "MA '0'"},
      {{"gripper", "goto", "abc"}, "COUNTS 'abc'"},
      {{"monitor", "nan"}, "SECONDS 'nan'"},
  };
  for (const Case& c : cases) {
    const Run r = run(on(s.sim, c.words));
    expect(r, 2, c.names);
  }
  // Nothing reached the servos: no packet, the goal where it was.
  assert_int_equal(s.sim.packets_handled(), packets_before);
  assert_int_equal(s.table16(1, ax12::kGoalPosition), goal_before);
}

void test_bad_options_are_refused_by_name(void**) {
  Servos s;
  for (const char* baud : {"abc", "0", "-9600", "57600abc", "3000000", ""}) {
    const Run r = run({"--port", s.sim.path(), "--baud", baud, "ping", "1"});
    expect(r, 2, std::string("--baud '") + baud + "'");
    assert_false(r.says("Success"));
  }
  expect(run({"--port", s.sim.path(), "--margin-us", "soon", "ping", "1"}), 2,
         "--margin-us 'soon'");
  expect(run({"--port", s.sim.path(), "ping", "1", "--baud"}), 2, "--baud needs a value");
  expect(run({"--port", s.sim.path(), "--bogus", "ping", "1"}), 2, "unknown option '--bogus'");
  expect(run({"--port", s.sim.path(), "spin", "1"}), 2, "unknown command 'spin'");
  expect(run({"--port", s.sim.path()}), 2, "usage:");
  // A good rate at which the servos are not: they stay silent.
  expect(run({"--port", s.sim.path(), "--baud", "57600", "ping", "1"}), 1, "TIMEOUT");
}

void test_help_documents_the_exit_statuses(void**) {
  const Run r = run({"--help"});
  expect(r, 0, "exit status:");
  assert_true(r.says("  0  done"));
  assert_true(r.says("  1  the device failed"));
  assert_true(r.says("  2  usage"));
}

void test_scan_finds_each_servo_once(void**) {
  Servos s;
  const Run r = run(on(s.sim, {"scan", "0", "3"}));
  expect(r, 0, "2 servo(s) found");
  assert_true(r.says("ID 1 at 1000000 baud, model 12 (AX-12A)"));
  assert_true(r.says("ID 2 at 1000000 baud, model 12 (AX-12A)"));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s ARMCTL\n", argv[0]);
    return 2;
  }
  g_program = argv[1];
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_success_exits_0),
      cmocka_unit_test(test_a_silent_servo_exits_1),
      cmocka_unit_test(test_a_servo_error_bit_exits_1),
      cmocka_unit_test(test_arguments_are_refused_whole_and_by_name),
      cmocka_unit_test(test_bad_options_are_refused_by_name),
      cmocka_unit_test(test_help_documents_the_exit_statuses),
      cmocka_unit_test(test_scan_finds_each_servo_once),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
