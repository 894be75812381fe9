// simdevices: serves the perching arm's simulated devices on
// pseudo-terminals, so that any program can talk to them as to the real
// ones: AX-12A servos (IDs 1 and 2) on one bus, the gripper board on
// another. Prints their paths, then takes fault commands on stdin until
// "quit", end of input or Ctrl-C.
#include <errno.h>
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
               "  servo overload ID on|off | overheat ID on|off | torque ID NM | powercycle ID\n"
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

struct Devices {
  sim_hal::SimServoBus& servos;
  const std::vector<std::uint8_t>& ids;
  sim_hal::SimGripperBoard& gripper;
  sim_hal::BusFaults servo_faults, gripper_faults;
};

// A servo ID word: 0..253, the whole word.
bool parse_id(const std::string& word, int* id) {
  char* end = nullptr;
  const long v = std::strtol(word.c_str(), &end, 10);
  if (word.empty() || *end != '\0' || v < 0 || v >= dynamixel::kBroadcastId) return false;
  *id = static_cast<int>(v);
  return true;
}

// Runs one command line and prints its answer; true for "quit".
bool run_command(const std::string& text, Devices* d) {
  std::istringstream in(text);
  std::string device, what;
  in >> device >> what;
  bool ok = true;
  if (device.empty()) return false;
  if (device == "quit") return true;
  if (device == "help") {
    usage(stdout);
  } else if (device == "status") {
    print_status(d->servos, d->ids, d->gripper);
  } else if (device == "servo" && (what == "overload" || what == "overheat")) {
    int id = -1;
    std::string id_word, state;
    in >> id_word >> state;
    bool on = false;
    ok = parse_id(id_word, &id) && parse_on_off(state, &on);
    if (ok) {
      sim_hal::SimServo s;
      d->servos.servo(static_cast<std::uint8_t>(id), &s);
      std::uint8_t bits = s.error_bits();
      const std::uint8_t bit =
          what == "overload" ? dynamixel::kErrorOverload : dynamixel::kErrorOverheating;
      bits = on ? (bits | bit) : (bits & ~bit);
      d->servos.force_error_bits(static_cast<std::uint8_t>(id), bits);
    }
  } else if (device == "servo" && what == "torque") {
    int id = -1;
    double nm = 0.0;
    std::string id_word;
    in >> id_word >> nm;
    ok = parse_id(id_word, &id) && !in.fail();
    if (ok) d->servos.set_external_torque(static_cast<std::uint8_t>(id), nm);
  } else if (device == "servo" && what == "powercycle") {
    int id = -1;
    std::string id_word;
    in >> id_word;
    ok = parse_id(id_word, &id);
    if (ok) d->servos.power_cycle(static_cast<std::uint8_t>(id));
  } else if (device == "servo") {
    ok = apply_line_fault(in, what, &d->servo_faults);
    if (ok) d->servos.set_faults(d->servo_faults);
  } else if (device == "gripper" && what == "handrail") {
    std::string value;
    in >> value;
    d->gripper.set_handrail_raw(value == "off" ? -1 : std::atoi(value.c_str()));
  } else if (device == "gripper") {
    ok = apply_line_fault(in, what, &d->gripper_faults);
    if (ok) d->gripper.set_faults(d->gripper_faults);
  } else {
    ok = false;
  }
  std::printf("%s\n", ok ? "ok" : "? not understood (type help)");
  std::fflush(stdout);
  return false;
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
        int id = -1;
        if (!parse_id(item, &id)) {
          std::fprintf(stderr, "simdevices: servo ID '%s' is not a number in 0..253\n",
                       item.c_str());
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
  Devices devices{servos, ids, gripper, {}, {}};
  // Commands are read with read() into a line buffer of our own, never
  // through stdio: poll() says nothing of what stdio has already buffered,
  // so with fgets a second command written in the same go as the first sat
  // unread until more input came.
  std::string pending;
  bool input_open = true, quit = false;
  while (!g_stop && !quit) {
    if (!input_open) {
      pause();  // stdin closed (a background service): run until a signal
      continue;
    }
    struct pollfd p = {0, POLLIN, 0};
    if (poll(&p, 1, 200) <= 0) continue;
    char buf[512];
    const ssize_t n = ::read(0, buf, sizeof(buf));
    if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
    if (n <= 0) {
      input_open = false;
      // A last command without its newline still counts.
      if (!pending.empty()) quit = run_command(pending, &devices);
      pending.clear();
      continue;
    }
    pending.append(buf, static_cast<std::size_t>(n));
    // Every whole line of what came, in order.
    std::size_t eol;
    while (!quit && (eol = pending.find('\n')) != std::string::npos) {
      const std::string line = pending.substr(0, eol);
      pending.erase(0, eol + 1);
      quit = run_command(line, &devices);
    }
    // A line longer than any command: dropped rather than grown forever.
    if (pending.size() > 4096) pending.clear();
  }
  servos.stop();
  gripper.stop();
  return 0;
}
