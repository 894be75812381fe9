// simdevices: serves the perching arm's simulated devices on
// pseudo-terminals, so that any program can talk to them as to the real
// ones: AX-12A servos (IDs 1 and 2) on one bus, the gripper board on
// another. Prints their paths, then takes fault commands on stdin until
// "quit", end of input or Ctrl-C.
#include <poll.h>
#include <signal.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "dynamixel/protocol1.hpp"
#include "sim_hal/sim_gripper.hpp"
#include "sim_hal/sim_servo_bus.hpp"

namespace {

volatile sig_atomic_t g_stop = 0;
void on_signal(int) {
  g_stop = 1;
}

void usage(FILE* out) {
  std::fprintf(out,
               "usage: simdevices [options]\n"
               "Serves simulated AX-12A servos and the gripper board on pseudo-terminals,\n"
               "prints their paths and runs until 'quit', end of input or Ctrl-C.\n\n"
               "options:\n"
               "  --ids LIST         servo IDs, comma separated (default 1,2)\n"
               "  --paths-file FILE  also write 'servos=PATH' and 'gripper=PATH' lines to FILE\n"
               "  -h, --help         this text\n\n"
               "commands on stdin (faults switch at once):\n"
               "  servo drop P | corrupt P | late US | noreply on|off | echo on|off\n"
               "  servo overload ID on|off | overheat ID on|off | torque ID NM\n"
               "  gripper drop P | corrupt P | noreply on|off | echo on|off | handrail COUNTS|off\n"
               "  status | help | quit\n");
}

bool parse_on_off(const std::string& word, bool* out) {
  if (word == "on")
    *out = true;
  else if (word == "off")
    *out = false;
  else
    return false;
  return true;
}

// Applies one fault to a fault set; false when the words make no sense.
bool apply_line_fault(std::istringstream& in, const std::string& what, sim_hal::BusFaults* f) {
  std::string value;
  in >> value;
  if (what == "drop")
    f->drop_byte_probability = std::atof(value.c_str());
  else if (what == "corrupt")
    f->corrupt_checksum_probability = std::atof(value.c_str());
  else if (what == "late")
    f->late_reply_us = static_cast<std::uint32_t>(std::atol(value.c_str()));
  else if (what == "noreply")
    return parse_on_off(value, &f->no_reply);
  else if (what == "echo")
    return parse_on_off(value, &f->echo);
  else
    return false;
  return !value.empty();
}

void print_status(sim_hal::SimServoBus& servos, const std::vector<std::uint8_t>& ids,
                  sim_hal::SimGripperBoard& gripper) {
  for (std::uint8_t id : ids) {
    sim_hal::SimServo s;
    if (!servos.servo(id, &s)) continue;
    std::printf("servo %u: position %.3f rad, temperature %.1f C, torque %s, error 0x%02x\n", id,
                s.position_rad(), s.temperature_c(), s.table(24) ? "on" : "off", s.error_bits());
  }
  const sim_hal::GripperSnapshot g = gripper.snapshot();
  std::printf("gripper: encoder %.0f, %.0f counts/s, %.2f A, pwm %d, %s, %s\n", g.position_raw,
              g.velocity_counts_s, g.current_a, g.pwm,
              g.calibrated ? "calibrated" : "not calibrated",
              g.safe_start ? "safe start" : "running");
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::uint8_t> ids = {1, 2};
  std::string paths_file;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "-h" || a == "--help") {
      usage(stdout);
      return 0;
    } else if (a == "--ids" && i + 1 < argc) {
      ids.clear();
      std::stringstream list(argv[++i]);
      std::string item;
      while (std::getline(list, item, ',')) {
        const long id = std::atol(item.c_str());
        if (id < 0 || id >= dynamixel::kBroadcastId) {
          std::fprintf(stderr, "simdevices: servo ID %s is outside 0..253\n", item.c_str());
          return 2;
        }
        ids.push_back(static_cast<std::uint8_t>(id));
      }
    } else if (a == "--paths-file" && i + 1 < argc) {
      paths_file = argv[++i];
    } else {
      std::fprintf(stderr, "simdevices: unknown option '%s' (see --help)\n", a.c_str());
      return 2;
    }
  }
  sim_hal::SimServoBus servos(ids);
  sim_hal::SimGripperBoard gripper;
  std::string error;
  if (!servos.start(&error) || !gripper.start(&error)) {
    std::fprintf(stderr, "simdevices: %s\n", error.c_str());
    return 1;
  }
  std::printf("servos (AX-12A, 1 Mbps): %s\ngripper board (115200 baud): %s\n",
              servos.path().c_str(), gripper.path().c_str());
  std::fflush(stdout);
  if (!paths_file.empty()) {
    FILE* f = std::fopen(paths_file.c_str(), "w");
    if (!f) {
      std::fprintf(stderr, "simdevices: cannot write %s: %s\n", paths_file.c_str(),
                   std::strerror(errno));
      return 1;
    }
    std::fprintf(f, "servos=%s\ngripper=%s\n", servos.path().c_str(), gripper.path().c_str());
    std::fclose(f);
  }
  signal(SIGINT, on_signal);
  signal(SIGTERM, on_signal);
  sim_hal::BusFaults servo_faults, gripper_faults;
  std::string line;
  char buf[512];
  bool input_open = true;
  while (!g_stop) {
    if (!input_open) {
      pause();  // stdin closed (a background service): run until a signal
      continue;
    }
    struct pollfd p = {0, POLLIN, 0};
    if (poll(&p, 1, 200) <= 0) continue;
    if (!std::fgets(buf, sizeof(buf), stdin)) {
      input_open = false;
      continue;
    }
    std::istringstream in(buf);
    std::string device, what;
    in >> device >> what;
    bool ok = true;
    if (device.empty()) continue;
    if (device == "quit") break;
    if (device == "help") {
      usage(stdout);
    } else if (device == "status") {
      print_status(servos, ids, gripper);
    } else if (device == "servo" && (what == "overload" || what == "overheat")) {
      int id = -1;
      std::string state;
      in >> id >> state;
      bool on = false;
      ok = id >= 0 && parse_on_off(state, &on);
      if (ok) {
        sim_hal::SimServo s;
        servos.servo(static_cast<std::uint8_t>(id), &s);
        std::uint8_t bits = s.error_bits();
        const std::uint8_t bit =
            what == "overload" ? dynamixel::kErrorOverload : dynamixel::kErrorOverheating;
        bits = on ? (bits | bit) : (bits & ~bit);
        servos.force_error_bits(static_cast<std::uint8_t>(id), bits);
      }
    } else if (device == "servo" && what == "torque") {
      int id = -1;
      double nm = 0.0;
      in >> id >> nm;
      ok = id >= 0;
      if (ok) servos.set_external_torque(static_cast<std::uint8_t>(id), nm);
    } else if (device == "servo") {
      ok = apply_line_fault(in, what, &servo_faults);
      if (ok) servos.set_faults(servo_faults);
    } else if (device == "gripper" && what == "handrail") {
      std::string value;
      in >> value;
      gripper.set_handrail_raw(value == "off" ? -1 : std::atoi(value.c_str()));
    } else if (device == "gripper") {
      ok = apply_line_fault(in, what, &gripper_faults);
      if (ok) gripper.set_faults(gripper_faults);
    } else {
      ok = false;
    }
    std::printf("%s\n", ok ? "ok" : "? not understood (type help)");
    std::fflush(stdout);
  }
  servos.stop();
  gripper.stop();
  return 0;
}
