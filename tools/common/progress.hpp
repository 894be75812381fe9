#pragma once
// A progress bar on stderr: redrawn in place on a terminal, a line every
// 10 % otherwise (CI logs).
#include <cstddef>
#include <string>

namespace tools {

class Progress {
 public:
  Progress(std::string label, std::size_t total);
  void update(std::size_t done, const std::string& note = "");
  void finish(const std::string& note = "");

 private:
  std::string label_;
  std::size_t total_;
  bool tty_;
  int last_decile_ = -1;
};

}  // namespace tools
