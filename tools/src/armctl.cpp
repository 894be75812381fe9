// armctl: a bench tool for the perching arm: the two AX-12A joints on the
// Dynamixel bus and the gripper board, on real ports or on the simulated
// devices (simdevices). Every failure says what and where.
#include <errno.h>
#include <poll.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "dynamixel/ax12.hpp"
#include "dynamixel/bus.hpp"
#include "gripper/gripper_board.hpp"
#include "hal/linux_serial_port.hpp"

namespace {

constexpr double kDegToRad = 3.14159265358979323846 / 180.0;
volatile sig_atomic_t g_stop = 0;
void on_signal(int) {
  g_stop = 1;
}

// Exit statuses: scripts tell a refused command line from a device that
// did not do what it was told.
constexpr int kExitOk = 0;
constexpr int kExitDevice = 1;  // no reply, a bad reply, a servo error bit, a port that fails
constexpr int kExitUsage = 2;   // the command line is refused before any device is touched

// The AX-12A's limits the arguments are checked against.
constexpr long kMaxServoId = 253;                    // 254 is broadcast
constexpr long kMinBaud = 7843, kMaxBaud = 1000000;  // the e-manual's range
constexpr int kMaxGripperValue = 0x3FFF;             // 14 bits on the board's protocol
constexpr long kMaxMarginUs = 10000000;
const double kMinDeg = dynamixel::ax12::position_rad(0) / kDegToRad;                 // -150.15
const double kMaxDeg = dynamixel::ax12::position_rad(1023) / kDegToRad;              // +149.85
const double kMaxDegS = 1023 * dynamixel::ax12::kRadPerSecPerSpeedUnit / kDegToRad;  // 681.3

void usage(FILE* out) {
  std::fprintf(
      out,
      "usage: armctl [options] COMMAND [ARGS]\n"
      "Bench tool for the perching arm's servos and gripper board.\n\n"
      "options:\n"
      "  --port DEV          Dynamixel bus (default /dev/ttyUSB0; a simdevices path works)\n"
      "  --baud N            its rate, %ld..%ld (default 1000000)\n"
      "  --margin-us N       time a reply may take beyond its bytes, 0..%ld (default 3000;\n"
      "                      more for a slow USB adapter or a loaded host)\n"
      "  --gripper-port DEV  gripper board (default /dev/ttyO1)\n"
      "  --echo              the adapter echoes what it sends (half duplex)\n"
      "  -h, --help          this text\n\n"
      "commands (ID 0..%ld, ADDRESS 0..%d, BYTE 0..255; numbers are checked whole):\n"
      "  scan [FIRST [LAST]]       ping IDs at 1 Mbps, 115200, 57600 (default 0..20)\n"
      "  ping ID\n"
      "  read ID ADDRESS LENGTH    raw control-table bytes (to the end of the table at most)\n"
      "  write ID ADDRESS BYTE...  raw control-table bytes\n"
      "  torque ID on|off\n"
      "  move ID DEGREES [DEG_S]   goal position %.2f..%.2f (0 = centre), speed above 0 up\n"
      "                            to %.1f (default 60)\n"
      "  recover ID                after an alarm shutdown\n"
      "  gripper version|state|calibrate|stop|open|close [MA]|goto COUNTS  (MA 1..%d,\n"
      "                            default 800; COUNTS 0..%d)\n"
      "  monitor [SECONDS]         joints 1 and 2 and the gripper at 10 Hz\n\n"
      "exit status:\n"
      "  0  done: the device answered and reported no error (scan: a servo found)\n"
      "  1  the device failed: no reply (TIMEOUT), a corrupt or wrong reply, a servo\n"
      "     error bit (e.g. OVERLOAD), or a port that cannot be opened\n"
      "  2  usage: an unknown command or option, or an argument refused (named in the\n"
      "     message); nothing was sent\n",
      kMinBaud, kMaxBaud, kMaxMarginUs, kMaxServoId, dynamixel::ax12::kTableSize - 1, kMinDeg,
      kMaxDeg, kMaxDegS, kMaxGripperValue, kMaxGripperValue);
}

// Reports a failure; returns the exit status to use.
int fail(const char* what, const std::string& detail, int status = kExitDevice) {
  std::fprintf(stderr, "armctl: %s: %s\n", what, detail.c_str());
  return status;
}

// A refused argument: names the command, the argument and what it must be.
int refuse(const std::string& cmd, const char* name, const std::string& word,
           const std::string& must_be) {
  std::fprintf(stderr, "armctl: %s: %s '%s' %s (see --help)\n", cmd.c_str(), name, word.c_str(),
               must_be.c_str());
  return kExitUsage;
}

// The whole word as a base-10 integer in [lo, hi]: no sign games, no
// trailing text, no overflow.
bool parse_integer(const std::string& word, long lo, long hi, long* out) {
  if (word.empty() || std::isspace(static_cast<unsigned char>(word[0]))) return false;
  errno = 0;
  char* end = nullptr;
  const long v = std::strtol(word.c_str(), &end, 10);
  if (errno != 0 || *end != '\0' || v < lo || v > hi) return false;
  *out = v;
  return true;
}

// The whole word as a finite number in [lo, hi] ("nan", "inf", "1e999",
// "12abc" are not).
bool parse_number(const std::string& word, double lo, double hi, double* out) {
  if (word.empty() || std::isspace(static_cast<unsigned char>(word[0]))) return false;
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(word.c_str(), &end);
  if (errno != 0 || *end != '\0' || !std::isfinite(v) || v < lo || v > hi) return false;
  *out = v;
  return true;
}

std::string range_text(long lo, long hi) {
  return "must be a whole number in " + std::to_string(lo) + ".." + std::to_string(hi);
}

std::string above_zero_text(double hi, int decimals) {
  char b[96];
  std::snprintf(b, sizeof(b), "must be a finite number above 0, at most %.*f", decimals, hi);
  return b;
}

std::string range_text(double lo, double hi, int decimals) {
  char b[96];
  std::snprintf(b, sizeof(b), "must be a finite number in %.*f..%.*f", decimals, lo, decimals, hi);
  return b;
}

std::string describe(const dynamixel::BusResult& r) {
  std::string s = dynamixel::to_string(r.status);
  if (r.status == dynamixel::BusStatus::kSerialError) {
    s += std::string(" (") + hal::to_string(r.serial_status) + ")";
  }
  for (int b = 0; b < 7; ++b) {
    if (r.servo_error & (1u << b)) s += std::string(" ") + dynamixel::error_bit_name(1u << b);
  }
  return s;
}

void print_gripper_state(const gripper::State& st) {
  std::printf("gripper: position %d counts, %d counts/s, %d mA, flags", st.position_counts,
              st.velocity_counts_s, st.current_ma);
  const char* names[] = {"calibrated",   "moving",     "holding", "stalled",
                         "over-current", "safe-start", "error"};
  for (int b = 0; b < 7; ++b)
    if (st.flags & (1u << b)) std::printf(" %s", names[b]);
  for (int b = 0; b < 7; ++b)
    if (st.error & (1u << b)) std::printf(" ERROR:%s", gripper::error_bit_name(1u << b));
  std::printf("\n");
}

}  // namespace

int main(int argc, char** argv) {
  std::string port_path = "/dev/ttyUSB0", gripper_path = "/dev/ttyO1";
  long baud = 1000000, margin_us = dynamixel::BusConfig{}.margin_us;
  bool echo = false;
  std::vector<std::string> words;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool takes_value =
        a == "--port" || a == "--gripper-port" || a == "--baud" || a == "--margin-us";
    if (takes_value && i + 1 >= argc) {
      std::fprintf(stderr, "armctl: option %s needs a value (see --help)\n", a.c_str());
      return kExitUsage;
    }
    if (a == "-h" || a == "--help") {
      usage(stdout);
      return kExitOk;
    } else if (a == "--port") {
      port_path = argv[++i];
    } else if (a == "--gripper-port") {
      gripper_path = argv[++i];
    } else if (a == "--baud") {
      const std::string value = argv[++i];
      if (!parse_integer(value, kMinBaud, kMaxBaud, &baud)) {
        std::fprintf(stderr, "armctl: --baud '%s' %s (the AX-12A's range; see --help)\n",
                     value.c_str(), range_text(kMinBaud, kMaxBaud).c_str());
        return kExitUsage;
      }
    } else if (a == "--margin-us") {
      const std::string value = argv[++i];
      if (!parse_integer(value, 0, kMaxMarginUs, &margin_us)) {
        std::fprintf(stderr, "armctl: --margin-us '%s' %s (see --help)\n", value.c_str(),
                     range_text(0, kMaxMarginUs).c_str());
        return kExitUsage;
      }
    } else if (a == "--echo") {
      echo = true;
    } else if (a.size() > 1 && a[0] == '-' && a[1] == '-') {
      // Only long options and -h are options: "-150" and "-inf" are words,
      // and get their argument's own message.
      std::fprintf(stderr, "armctl: unknown option '%s' (see --help)\n", a.c_str());
      return kExitUsage;
    } else {
      words.push_back(a);
    }
  }
  if (words.empty()) {
    usage(stderr);
    return kExitUsage;
  }
  const std::string& cmd = words[0];
  auto arg = [&](std::size_t k) { return k < words.size() ? words[k] : std::string(); };

  // Every argument is checked before any port is opened.
  struct Limits {
    std::size_t min_words, max_words;
  };
  Limits limits{1, 1};
  if (cmd == "scan") {
    limits = {1, 3};
  } else if (cmd == "ping" || cmd == "recover") {
    limits = {2, 2};
  } else if (cmd == "read") {
    limits = {4, 4};
  } else if (cmd == "write") {
    limits = {4, 3 + dynamixel::ax12::kTableSize};
  } else if (cmd == "torque") {
    limits = {3, 3};
  } else if (cmd == "move") {
    limits = {3, 4};
  } else if (cmd == "gripper") {
    limits = {2, 3};
  } else if (cmd == "monitor") {
    limits = {1, 2};
  } else {
    std::fprintf(stderr, "armctl: unknown command '%s' (see --help)\n", cmd.c_str());
    return kExitUsage;
  }
  if (words.size() < limits.min_words) {
    std::fprintf(stderr, "armctl: %s: missing arguments (see --help)\n", cmd.c_str());
    return kExitUsage;
  }
  if (words.size() > limits.max_words) {
    return refuse(cmd, "argument", words[limits.max_words], "is one too many");
  }
  long id = 0;
  const bool has_id = cmd != "scan" && cmd != "gripper" && cmd != "monitor";
  if (has_id && !parse_integer(arg(1), 0, kMaxServoId, &id)) {
    return refuse(cmd, "ID", arg(1), range_text(0, kMaxServoId));
  }
  const long table_end = dynamixel::ax12::kTableSize;
  long first = 0, last = 20, address = 0, length = 0;
  std::uint8_t data[dynamixel::ax12::kTableSize];
  std::size_t n_data = 0;
  double degrees = 0.0, deg_s = 60.0, seconds = 1e9;
  bool torque_on = false;
  long gripper_value = 0;
  if (cmd == "scan") {
    if (words.size() > 1 && !parse_integer(arg(1), 0, kMaxServoId, &first)) {
      return refuse(cmd, "FIRST", arg(1), range_text(0, kMaxServoId));
    }
    if (words.size() > 2 && !parse_integer(arg(2), first, kMaxServoId, &last)) {
      return refuse(cmd, "LAST", arg(2), range_text(first, kMaxServoId));
    }
    if (words.size() == 2) last = std::max(first, last);
  } else if (cmd == "read" || cmd == "write") {
    if (!parse_integer(arg(2), 0, table_end - 1, &address)) {
      return refuse(cmd, "ADDRESS", arg(2), range_text(0, table_end - 1));
    }
    if (cmd == "read" && !parse_integer(arg(3), 1, table_end - address, &length)) {
      return refuse(cmd, "LENGTH", arg(3), range_text(1, table_end - address));
    }
    if (cmd == "write") {
      if (static_cast<long>(words.size() - 3) > table_end - address) {
        return refuse(
            cmd, "BYTE", words[3 + static_cast<std::size_t>(table_end - address)],
            "is past the end of the control table (" + std::to_string(table_end) + " bytes)");
      }
      for (std::size_t k = 3; k < words.size(); ++k) {
        long b = 0;
        if (!parse_integer(words[k], 0, 255, &b))
          return refuse(cmd, "BYTE", words[k], range_text(0, 255));
        data[n_data++] = static_cast<std::uint8_t>(b);
      }
    }
  } else if (cmd == "torque") {
    if (arg(2) != "on" && arg(2) != "off") return refuse(cmd, "state", arg(2), "must be on or off");
    torque_on = arg(2) == "on";
  } else if (cmd == "move") {
    if (!parse_number(arg(2), kMinDeg, kMaxDeg, &degrees)) {
      return refuse(cmd, "DEGREES", arg(2), range_text(kMinDeg, kMaxDeg, 2));
    }
    // Above 0: a moving speed of 0 is the servo's "no speed control".
    if (words.size() > 3 && (!parse_number(arg(3), 0.0, kMaxDegS, &deg_s) || deg_s <= 0.0)) {
      return refuse(cmd, "DEG_S", arg(3), above_zero_text(kMaxDegS, 1));
    }
  } else if (cmd == "gripper") {
    const std::string what = arg(1);
    const bool known = what == "version" || what == "state" || what == "calibrate" ||
                       what == "stop" || what == "open" || what == "close" || what == "goto";
    if (!known)
      return fail("gripper", "unknown subcommand '" + what + "' (see --help)", kExitUsage);
    if (what == "goto" && words.size() < 3) {
      return fail("gripper", "goto needs COUNTS (see --help)", kExitUsage);
    }
    if (words.size() > 2 && what != "close" && what != "goto") {
      return refuse(cmd + " " + what, "argument", arg(2), "is one too many");
    }
    gripper_value = 800;
    if (what == "close" && words.size() > 2 &&
        !parse_integer(arg(2), 1, kMaxGripperValue, &gripper_value)) {
      return refuse("gripper close", "MA", arg(2), range_text(1, kMaxGripperValue));
    }
    if (what == "goto" && !parse_integer(arg(2), 0, kMaxGripperValue, &gripper_value)) {
      return refuse("gripper goto", "COUNTS", arg(2), range_text(0, kMaxGripperValue));
    }
  } else if (cmd == "monitor") {
    if (words.size() > 1 && (!parse_number(arg(1), 0.0, 1e9, &seconds) || seconds <= 0.0)) {
      return refuse(cmd, "SECONDS", arg(1), above_zero_text(1e9, 0));
    }
  }

  hal::MonotonicClock clock;
  hal::LinuxSerialPort bus_port(&clock), gripper_port(&clock);
  std::string error;
  const bool needs_bus = cmd != "gripper";
  const bool needs_gripper = cmd == "gripper" || cmd == "monitor";
  if (needs_bus) {
    if (bus_port.open(port_path, static_cast<std::uint32_t>(baud), &error) !=
        hal::SerialStatus::kOk) {
      return fail("Dynamixel port", error + " (is the adapter plugged in? see --port)");
    }
    bus_port.set_echo_suppression(echo);
  }
  if (needs_gripper) {
    if (gripper_port.open(gripper_path, 115200, &error) != hal::SerialStatus::kOk) {
      return fail("gripper port", error + " (see --gripper-port)");
    }
  }
  dynamixel::BusConfig bus_config;
  bus_config.margin_us = static_cast<std::uint32_t>(margin_us);
  dynamixel::Bus bus(bus_port, clock, bus_config);
  gripper::GripperBoard board(gripper_port, clock);
  const std::uint8_t sid = static_cast<std::uint8_t>(id);

  if (cmd == "scan") {
    const std::uint32_t bauds[] = {1000000, 115200, 57600};
    dynamixel::ax12::ScanHit hits[64];
    const std::size_t n = dynamixel::ax12::scan(bus, bauds, 3, static_cast<std::uint8_t>(first),
                                                static_cast<std::uint8_t>(last), hits, 64);
    for (std::size_t k = 0; k < n; ++k) {
      std::printf("ID %u at %u baud, model %u%s\n", hits[k].id, hits[k].baud, hits[k].model,
                  hits[k].model == dynamixel::ax12::kModelAx12A ? " (AX-12A)" : "");
    }
    std::printf("%zu servo(s) found\n", n);
    return n > 0 ? kExitOk : kExitDevice;
  }
  if (cmd == "ping") {
    const dynamixel::BusResult r = bus.ping(sid);
    std::printf("ID %ld: %s\n", id, describe(r).c_str());
    return r.ok() ? kExitOk : kExitDevice;
  }
  if (cmd == "read") {
    std::uint8_t out[dynamixel::ax12::kTableSize];
    const dynamixel::BusResult r =
        bus.read(sid, static_cast<std::uint8_t>(address), static_cast<std::uint8_t>(length), out);
    if (r.status != dynamixel::BusStatus::kOk) return fail("read", describe(r));
    for (long k = 0; k < length; ++k) std::printf("%ld: %u\n", address + k, out[k]);
    // The bytes are good; the servo's error bits still make it a failure.
    if (!r.ok()) return fail("read", describe(r));
    return kExitOk;
  }
  if (cmd == "write" || cmd == "torque" || cmd == "move" || cmd == "recover") {
    dynamixel::ax12::Servo servo(bus, sid);
    dynamixel::BusResult r;
    if (cmd == "write") {
      r = bus.write(sid, static_cast<std::uint8_t>(address), data,
                    static_cast<std::uint8_t>(n_data));
    } else if (cmd == "torque") {
      r = servo.set_torque_enable(torque_on);
    } else if (cmd == "recover") {
      r = servo.recover_from_alarm();
    } else {
      r = servo.set_moving_speed(deg_s * kDegToRad);
      if (r.ok()) r = servo.set_torque_enable(true);
      if (r.ok()) r = servo.set_goal_position(degrees * kDegToRad);
    }
    std::printf("%s\n", describe(r).c_str());
    return r.ok() ? kExitOk : kExitDevice;
  }
  if (cmd == "gripper") {
    const std::string what = arg(1);
    gripper::Status s = gripper::Status::kInvalidArgument;
    if (what == "version") {
      gripper::Version v;
      s = board.get_version(&v);
      if (s == gripper::Status::kOk)
        std::printf("protocol %u, firmware %u.%u, board 0x%02x\n", v.protocol, v.major, v.minor,
                    v.board_id);
    } else if (what == "state") {
      gripper::State st;
      s = board.get_state(&st);
      if (s == gripper::Status::kOk) print_gripper_state(st);
    } else if (what == "stop") {
      s = board.stop();
    } else {
      s = board.exit_safe_start();
      if (s == gripper::Status::kOk) {
        if (what == "calibrate") s = board.calibrate();
        if (what == "open") s = board.open(0.6);
        if (what == "close") s = board.close(0.6, static_cast<int>(gripper_value));
        if (what == "goto") s = board.go_to(static_cast<int>(gripper_value), 0.6);
      }
    }
    if (s != gripper::Status::kOk) {
      return fail("gripper", std::string(gripper::to_string(s)) + " on " + gripper_path);
    }
    return kExitOk;
  }
  // monitor
  signal(SIGINT, on_signal);
  dynamixel::ax12::Servo joints[2] = {{bus, 1}, {bus, 2}};
  const auto start = std::chrono::steady_clock::now();
  auto next = start;
  while (!g_stop) {
    next += std::chrono::milliseconds(100);
    if (std::chrono::duration<double>(next - start).count() > seconds) break;
    for (auto& j : joints) {
      dynamixel::ax12::ServoState st;
      const dynamixel::BusResult r = j.read_state(&st);
      if (r.status == dynamixel::BusStatus::kOk) {
        std::printf("joint %u: %7.2f deg %7.2f deg/s load %+5.2f %4.1f V %3d C%s | ", j.id(),
                    st.position_rad / kDegToRad, st.speed_rad_s / kDegToRad, st.load_fraction,
                    st.voltage_v, st.temperature_c, st.moving ? " moving" : "");
      } else {
        std::printf("joint %u: %s | ", j.id(), describe(r).c_str());
      }
    }
    gripper::State gs;
    const gripper::Status s = board.get_state(&gs);
    if (s == gripper::Status::kOk)
      print_gripper_state(gs);
    else
      std::printf("gripper: %s\n", gripper::to_string(s));
    std::fflush(stdout);
    std::this_thread::sleep_until(next);
  }
  return kExitOk;
}
