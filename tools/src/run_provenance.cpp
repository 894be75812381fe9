#include "run_provenance.hpp"

#include <unistd.h>

#include <cstdio>
#include <ctime>
#include <fstream>

namespace tools {
namespace {

// The first line a shell command prints (empty if it fails or prints none).
std::string first_line_of(const std::string& command) {
  FILE* p = popen(command.c_str(), "r");
  if (p == nullptr) return "";
  char buf[256];
  std::string line;
  if (std::fgets(buf, sizeof buf, p) != nullptr) line = buf;
  const int status = pclose(p);
  if (status != 0) return "";
  while (!line.empty() && (line.back() == '\n' || line.back() == '\r')) line.pop_back();
  return line;
}

std::string commit_of(const std::string& dir) {
  const std::string git = "git -C '" + dir + "' ";
  const std::string sha = first_line_of(git + "rev-parse --short HEAD 2>/dev/null");
  if (sha.empty()) return "not a git checkout";
  // Any tracked or untracked change: the figures are not the commit's alone.
  // The kept evaluation's own files are output, not input (tools/run
  // --publish rewrites them before its second run).
  const std::string changed = first_line_of(git +
                                            "status --porcelain --untracked-files=normal -- . "
                                            "':(exclude)estimator/doc/evaluation' 2>/dev/null");
  return "commit " + sha + (changed.empty() ? "" : " (with local changes)");
}

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("model name", 0) == 0) {
      const std::size_t colon = line.find(':');
      if (colon != std::string::npos) return line.substr(line.find_first_not_of(' ', colon + 1));
    }
  }
  return "unknown CPU";
}

}  // namespace

std::string run_provenance(const std::string& source_dir) {
  char when[32] = "unknown time";
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  if (gmtime_r(&now, &utc) != nullptr) std::strftime(when, sizeof when, "%Y-%m-%d %H:%M UTC", &utc);
  const long cores = sysconf(_SC_NPROCESSORS_ONLN);
#ifdef NDEBUG
  const char* build = "optimised build";
#else
  const char* build = "debug build (times are not the flight's)";
#endif
  return std::string(when) + ", " + commit_of(source_dir) + ", " + cpu_model() + " (" +
         std::to_string(cores) + " cores), " + build;
}

}  // namespace tools
