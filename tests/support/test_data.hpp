#pragma once
// Paths of the recorded test frames in tests/data (CTest sets HRP_SOURCE_DIR).
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

namespace testing_support {

inline std::string data_path(const std::string& name) {
  const char* root = std::getenv("HRP_SOURCE_DIR");
  return std::string(root ? root : ".") + "/tests/data/" + name;
}

inline std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace testing_support
