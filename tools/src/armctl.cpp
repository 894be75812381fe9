// armctl: a bench tool for the perching arm: the two AX-12A joints on the
// Dynamixel bus and the gripper board, on real ports or on the simulated
// devices (simdevices). Every failure says what and where.
#include <poll.h>
#include <signal.h>
#include <unistd.h>

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

void usage(FILE* out) {
  std::fprintf(
      out,
      "usage: armctl [options] COMMAND [ARGS]\n"
      "Bench tool for the perching arm's servos and gripper board.\n\n"
      "options:\n"
      "  --port DEV          Dynamixel bus (default /dev/ttyUSB0; a simdevices path works)\n"
      "  --baud N            its rate (default 1000000)\n"
      "  --gripper-port DEV  gripper board (default /dev/ttyO1)\n"
      "  --echo              the adapter echoes what it sends (half duplex)\n"
      "  -h, --help          this text\n\n"
      "commands:\n"
      "  scan [FIRST LAST]         ping IDs at 1 Mbps, 115200, 57600 (default 0..20)\n"
      "  ping ID\n"
      "  read ID ADDRESS LENGTH    raw control-table bytes\n"
      "  write ID ADDRESS BYTE...  raw control-table bytes\n"
      "  torque ID on|off\n"
      "  move ID DEGREES [DEG_S]   goal position (0 = centre), speed (default 60)\n"
      "  recover ID                after an alarm shutdown\n"
      "  gripper version|state|calibrate|stop|open|close [MA]|goto COUNTS\n"
      "  monitor [SECONDS]         joints 1 and 2 and the gripper at 10 Hz\n");
}

// Reports a failure; returns the exit status to use (1: the device, 2: usage).
int fail(const char* what, const std::string& detail, int status = 1) {
  std::fprintf(stderr, "armctl: %s: %s\n", what, detail.c_str());
  return status;
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
  long baud = 1000000;
  bool echo = false;
  std::vector<std::string> words;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "-h" || a == "--help") {
      usage(stdout);
      return 0;
    } else if (a == "--port" && i + 1 < argc) {
      port_path = argv[++i];
    } else if (a == "--gripper-port" && i + 1 < argc) {
      gripper_path = argv[++i];
    } else if (a == "--baud" && i + 1 < argc) {
      baud = std::atol(argv[++i]);
    } else if (a == "--echo") {
      echo = true;
    } else if (a.size() > 1 && a[0] == '-' && !std::isdigit(static_cast<unsigned char>(a[1]))) {
      std::fprintf(stderr, "armctl: unknown option '%s' (see --help)\n", a.c_str());
      return 2;
    } else {
      words.push_back(a);
    }
  }
  if (words.empty()) {
    usage(stderr);
    return 2;
  }
  auto arg = [&](std::size_t k) { return k < words.size() ? words[k] : std::string(); };
  auto num = [&](std::size_t k) { return std::atol(arg(k).c_str()); };
  hal::MonotonicClock clock;
  const std::string& cmd = words[0];

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
  dynamixel::Bus bus(bus_port, clock);
  gripper::GripperBoard board(gripper_port, clock);

  if (cmd == "scan") {
    const std::uint32_t bauds[] = {1000000, 115200, 57600};
    const long first = words.size() > 1 ? num(1) : 0, last = words.size() > 2 ? num(2) : 20;
    dynamixel::ax12::ScanHit hits[64];
    const std::size_t n = dynamixel::ax12::scan(bus, bauds, 3, static_cast<std::uint8_t>(first),
                                                static_cast<std::uint8_t>(last), hits, 64);
    for (std::size_t k = 0; k < n; ++k) {
      std::printf("ID %u at %u baud, model %u%s\n", hits[k].id, hits[k].baud, hits[k].model,
                  hits[k].model == dynamixel::ax12::kModelAx12A ? " (AX-12A)" : "");
    }
    std::printf("%zu servo(s) found\n", n);
    return 0;
  }
  if (cmd == "ping") {
    const dynamixel::BusResult r = bus.ping(static_cast<std::uint8_t>(num(1)));
    std::printf("ID %ld: %s\n", num(1), describe(r).c_str());
    return r.status == dynamixel::BusStatus::kOk ? 0 : 1;
  }
  if (cmd == "read") {
    std::uint8_t out[64];
    const long len = num(3);
    if (len <= 0 || len > 64) return fail("read", "LENGTH must be 1..64", 2);
    const dynamixel::BusResult r =
        bus.read(static_cast<std::uint8_t>(num(1)), static_cast<std::uint8_t>(num(2)),
                 static_cast<std::uint8_t>(len), out);
    if (r.status != dynamixel::BusStatus::kOk) return fail("read", describe(r));
    for (long k = 0; k < len; ++k) std::printf("%ld: %u\n", num(2) + k, out[k]);
    return 0;
  }
  if (cmd == "write") {
    std::uint8_t data[60];
    std::size_t n = 0;
    for (std::size_t k = 3; k < words.size() && n < sizeof(data); ++k)
      data[n++] = static_cast<std::uint8_t>(num(k));
    if (n == 0) return fail("write", "give at least one BYTE", 2);
    const dynamixel::BusResult r =
        bus.write(static_cast<std::uint8_t>(num(1)), static_cast<std::uint8_t>(num(2)), data,
                  static_cast<std::uint8_t>(n));
    std::printf("%s\n", describe(r).c_str());
    return r.ok();
  }
  if (cmd == "torque" || cmd == "move" || cmd == "recover") {
    dynamixel::ax12::Servo servo(bus, static_cast<std::uint8_t>(num(1)));
    dynamixel::BusResult r;
    if (cmd == "torque") {
      r = servo.set_torque_enable(arg(2) == "on");
    } else if (cmd == "recover") {
      r = servo.recover_from_alarm();
    } else {
      const double speed = words.size() > 3 ? std::atof(arg(3).c_str()) : 60.0;
      r = servo.set_moving_speed(speed * kDegToRad);
      if (r.ok()) r = servo.set_torque_enable(true);
      if (r.ok()) r = servo.set_goal_position(std::atof(arg(2).c_str()) * kDegToRad);
    }
    std::printf("%s\n", describe(r).c_str());
    return r.ok();
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
    } else if (what == "calibrate" || what == "open" || what == "close" || what == "goto") {
      s = board.exit_safe_start();
      if (s == gripper::Status::kOk) {
        if (what == "calibrate") s = board.calibrate();
        if (what == "open") s = board.open(0.6);
        if (what == "close")
          s = board.close(0.6, words.size() > 2 ? static_cast<int>(num(2)) : 800);
        if (what == "goto") s = board.go_to(static_cast<int>(num(2)), 0.6);
      }
    } else if (what == "stop") {
      s = board.stop();
    } else {
      return fail("gripper", "unknown subcommand '" + what + "' (see --help)", 2);
    }
    if (s != gripper::Status::kOk) {
      return fail("gripper", std::string(gripper::to_string(s)) + " on " + gripper_path);
    }
    return 0;
  }
  if (cmd == "monitor") {
    signal(SIGINT, on_signal);
    const double seconds = words.size() > 1 ? std::atof(arg(1).c_str()) : 1e9;
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
    return 0;
  }
  std::fprintf(stderr, "armctl: unknown command '%s' (see --help)\n", cmd.c_str());
  return 2;
}
