#pragma once
// Paths of the recorded test frames in tests/data and of other source files
// (CTest sets HRP_SOURCE_DIR), reading a file whole, and a scratch folder.
#include <stdlib.h>  // mkdtemp

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace testing_support {

inline std::string data_path(const std::string& name) {
  const char* root = std::getenv("HRP_SOURCE_DIR");
  return std::string(root ? root : ".") + "/tests/data/" + name;
}

// A file of the source tree by its path from the root ("sim_hal/...").
inline std::string source_path(const std::string& rel) {
  const char* root = std::getenv("HRP_SOURCE_DIR");
  return std::string(root ? root : ".") + "/" + rel;
}

inline std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// A folder made under /tmp for one test program (`prefix` names it), removed
// with everything in it when the object goes. path() is empty if it could
// not be made.
class ScratchDir {
 public:
  explicit ScratchDir(const std::string& prefix) {
    std::string pattern = "/tmp/" + prefix + "_XXXXXX";
    if (mkdtemp(pattern.data())) path_ = pattern;
  }
  ~ScratchDir() {
    std::error_code ec;
    if (!path_.empty()) std::filesystem::remove_all(path_, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

}  // namespace testing_support
