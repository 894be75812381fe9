#include "progress.hpp"

#include <unistd.h>

#include <cstdio>

namespace tools {

Progress::Progress(std::string label, std::size_t total)
    : label_(std::move(label)), total_(total ? total : 1), tty_(isatty(STDERR_FILENO) != 0) {}

void Progress::update(std::size_t done, const std::string& note) {
  const int percent = static_cast<int>(100 * done / total_);
  if (tty_) {
    constexpr int kWidth = 30;
    const int filled = percent * kWidth / 100;
    std::fprintf(stderr, "\r%-22s [%.*s%*s] %3d%% %zu/%zu %s\033[K", label_.c_str(), filled,
                 "##############################", kWidth - filled, "", percent, done, total_,
                 note.c_str());
    std::fflush(stderr);
  } else if (percent / 10 != last_decile_) {
    last_decile_ = percent / 10;
    std::fprintf(stderr, "%s: %d%% (%zu/%zu) %s\n", label_.c_str(), percent, done, total_,
                 note.c_str());
  }
}

void Progress::finish(const std::string& note) {
  update(total_, note);
  if (tty_) std::fprintf(stderr, "\n");
}

}  // namespace tools
