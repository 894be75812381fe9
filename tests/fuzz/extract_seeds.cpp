// Seeds for the LCM receiver fuzzers (fuzz_lcm_receiver.cpp) from a real
// LCM log, and the small sample logs they are taken from. Real messages
// get the fuzzers past the fingerprint, the layout and the content checks
// at once; random search would not.
//
//   extract_seeds [--max N] LOG OUT CHANNEL[=TYPE]...
//     Up to N messages (default 20, spread over the log) of each channel,
//     each as OUT/corpus_fuzz_TYPE/seed-CHANNEL-K: the fuzzer's selector
//     byte (0x80: the bytes as they are, a replay receiver, the queue
//     drained) and then the message's bytes as logged.
//   extract_seeds --cut [--max N] LOG OUT_LOG CHANNEL...
//     An LCM log of up to N messages (spread as above) of each channel,
//     in their order and with their times.
// TYPE defaults to the channel's type on the robot (ARM_STATE:
// arm_state_t, ...). Exit status: 0 done, 1 a channel has no messages in
// the log, 2 bad arguments or a log that cannot be read.
#include <lcm/lcm-cpp.hpp>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace {

constexpr unsigned char kSelectorAsLogged = 0x80;

const char* const kUsage =
    "usage: extract_seeds [--max N] LOG OUT CHANNEL[=TYPE]...\n"
    "       extract_seeds --cut [--max N] LOG OUT_LOG CHANNEL...\n"
    "Seeds for tests/fuzz/fuzz_lcm_receiver.cpp from an LCM log: up to N messages\n"
    "(default 20, spread over the log) of each CHANNEL, written as\n"
    "OUT/corpus_fuzz_TYPE/seed-CHANNEL-K (a selector byte 0x80, then the bytes as\n"
    "logged). TYPE defaults to the channel's message type on the robot.\n"
    "With --cut: a new LCM log OUT_LOG of up to N messages of each CHANNEL instead.\n"
    "Exit status: 0 done, 1 a channel has no messages in LOG, 2 bad arguments or\n"
    "an unreadable LOG.\n";

// The robot's channels and their types (fsw_app/include/fsw_app/lcm_hub.hpp).
const std::map<std::string, std::string> kChannelTypes = {
    {"ARM_STATE", "arm_state_t"},
    {"ROBOT_POSE", "robot_pose_t"},
    {"TRUTH_POSE", "robot_pose_t"},
    {"HANDRAIL_ESTIMATE", "handrail_estimate_t"},
    {"APPROACH_STATUS", "approach_status_t"},
    {"ESTIMATOR_HEALTH", "estimator_health_t"},
    {"PERCH_COMMAND", "perch_command_t"},
    {"IMU_SAMPLE", "imu_sample_t"},
    {"GP_POSE", "gp_pose_t"},
    {"BODY_VELOCITY_COMMAND", "body_velocity_command_t"},
    {"DEPTH_FRAME", "depth_frame_t"},
    {"INPUT_HEALTH", "input_health_t"},
    {"LOCALIZATION_HEALTH", "localization_health_t"},
};

int usage_error(const std::string& what) {
  std::fprintf(stderr, "extract_seeds: %s (see extract_seeds --help)\n", what.c_str());
  return 2;
}

// Opens LOG for reading, or says why not. Null on failure.
std::unique_ptr<lcm::LogFile> open_log(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    std::fprintf(stderr, "extract_seeds: %s: is a folder, not an LCM log\n", path.c_str());
    return nullptr;
  }
  std::ifstream probe(path, std::ios::binary);
  if (!probe) {
    std::fprintf(stderr, "extract_seeds: cannot read %s: %s\n", path.c_str(), std::strerror(errno));
    return nullptr;
  }
  auto log = std::make_unique<lcm::LogFile>(path, "r");
  if (!log->good()) {
    std::fprintf(stderr, "extract_seeds: cannot open %s as an LCM log\n", path.c_str());
    return nullptr;
  }
  return log;
}

// Messages per channel in the log; false when it holds none at all.
bool count_events(const std::string& path, std::map<std::string, std::size_t>* counts) {
  std::unique_ptr<lcm::LogFile> log = open_log(path);
  if (!log) return false;
  std::size_t n = 0;
  while (const lcm::LogEvent* ev = log->readNextEvent()) {
    ++(*counts)[ev->channel];
    ++n;
  }
  if (n == 0) {
    std::fprintf(stderr, "extract_seeds: %s holds no LCM events (not an LCM log?)\n", path.c_str());
    return false;
  }
  return true;
}

// Which of a channel's `total` messages to take: `max` of them, spread
// evenly, first and last included.
bool take(std::size_t index, std::size_t total, std::size_t max) {
  if (total <= max) return true;
  if (max == 0) return false;
  if (max == 1) return index == 0;
  // The k-th pick is at round(k * (total - 1) / (max - 1)).
  for (std::size_t k = 0; k < max; ++k) {
    if ((k * (total - 1) + (max - 1) / 2) / (max - 1) == index) return true;
  }
  return false;
}

struct Wanted {
  std::string type;
  std::size_t total = 0;  // in the log
  std::size_t seen = 0;
  std::size_t taken = 0;
};

}  // namespace

int main(int argc, char** argv) {
  bool cut = false;
  std::size_t max = 20;
  std::vector<std::string> positional;
  for (int k = 1; k < argc; ++k) {
    const std::string arg = argv[k];
    if (arg == "-h" || arg == "--help") {
      std::fputs(kUsage, stdout);
      return 0;
    } else if (arg == "--cut") {
      cut = true;
    } else if (arg == "--max") {
      if (k + 1 >= argc) return usage_error("--max needs a number");
      const std::string value = argv[++k];
      char* end = nullptr;
      errno = 0;
      const unsigned long n = std::strtoul(value.c_str(), &end, 10);
      if (value.empty() || *end != '\0' || errno != 0 || n == 0 || n > 100000 || value[0] == '-') {
        return usage_error("--max " + value + ": not a count from 1 to 100000");
      }
      max = n;
    } else if (arg.size() > 1 && arg[0] == '-') {
      return usage_error("unknown option " + arg);
    } else {
      positional.push_back(arg);
    }
  }
  if (positional.size() < 3) return usage_error("needs a log, an output and a channel");
  const std::string log_path = positional[0];
  const std::string out = positional[1];

  std::map<std::string, Wanted> wanted;
  for (std::size_t k = 2; k < positional.size(); ++k) {
    std::string channel = positional[k];
    std::string type;
    const std::size_t eq = channel.find('=');
    if (eq != std::string::npos) {
      if (cut) return usage_error("--cut takes channels only: " + channel);
      type = channel.substr(eq + 1);
      channel.resize(eq);
      if (channel.empty() || type.empty() || type.find('/') != std::string::npos) {
        return usage_error("bad CHANNEL=TYPE: " + positional[k]);
      }
    } else if (!cut) {
      const auto it = kChannelTypes.find(channel);
      if (it == kChannelTypes.end()) {
        return usage_error("unknown channel " + channel + " (name its type: " + channel + "=TYPE)");
      }
      type = it->second;
    }
    if (channel.find('/') != std::string::npos) return usage_error("bad channel: " + channel);
    if (wanted.count(channel) != 0) return usage_error("channel named twice: " + channel);
    wanted[channel].type = type;
  }

  std::map<std::string, std::size_t> counts;
  if (!count_events(log_path, &counts)) return 2;
  int status = 0;
  for (auto& [channel, w] : wanted) {
    w.total = counts.count(channel) != 0 ? counts[channel] : 0;
    if (w.total == 0) {
      std::fprintf(stderr, "extract_seeds: no %s messages in %s\n", channel.c_str(),
                   log_path.c_str());
      status = 1;
    }
  }

  std::unique_ptr<lcm::LogFile> out_log;
  if (cut) {
    std::error_code ec;
    if (std::filesystem::equivalent(log_path, out, ec)) {
      return usage_error("the cut " + out + " would overwrite the log it is cut from");
    }
    out_log = std::make_unique<lcm::LogFile>(out, "w");
    if (!out_log->good()) {
      std::fprintf(stderr, "extract_seeds: cannot write %s: %s\n", out.c_str(),
                   std::strerror(errno));
      return 2;
    }
  } else {
    for (const auto& [channel, w] : wanted) {
      std::error_code ec;
      std::filesystem::create_directories(out + "/corpus_fuzz_" + w.type, ec);
      if (ec) {
        std::fprintf(stderr, "extract_seeds: cannot make %s/corpus_fuzz_%s: %s\n", out.c_str(),
                     w.type.c_str(), ec.message().c_str());
        return 2;
      }
    }
  }

  std::unique_ptr<lcm::LogFile> log = open_log(log_path);
  if (!log) return 2;
  std::int64_t eventnum = 0;
  while (const lcm::LogEvent* ev = log->readNextEvent()) {
    const auto it = wanted.find(ev->channel);
    if (it == wanted.end()) continue;
    Wanted& w = it->second;
    const std::size_t index = w.seen++;
    if (!take(index, w.total, max)) continue;
    if (cut) {
      lcm::LogEvent copy = *ev;
      copy.eventnum = eventnum++;
      if (out_log->writeEvent(&copy) != 0) {
        std::fprintf(stderr, "extract_seeds: cannot write %s\n", out.c_str());
        return 2;
      }
    } else {
      const std::string path =
          out + "/corpus_fuzz_" + w.type + "/seed-" + ev->channel + "-" + std::to_string(w.taken);
      std::ofstream file(path, std::ios::binary | std::ios::trunc);
      file.put(static_cast<char>(kSelectorAsLogged));
      file.write(static_cast<const char*>(ev->data), ev->datalen);
      if (!file.flush()) {
        std::fprintf(stderr, "extract_seeds: cannot write %s\n", path.c_str());
        return 2;
      }
    }
    ++w.taken;
  }
  for (const auto& [channel, w] : wanted) {
    if (w.taken == 0) continue;
    std::printf("extract_seeds: %s: %zu of %zu messages -> %s\n", channel.c_str(), w.taken, w.total,
                cut ? out.c_str() : (out + "/corpus_fuzz_" + w.type).c_str());
  }
  return status;
}
