#include "output_dir.hpp"

#include <filesystem>
#include <system_error>

namespace tools {

bool make_output_dir(const std::string& path, std::string* error) {
  namespace fs = std::filesystem;
  if (path.empty()) {
    *error = "the output folder's name is empty";
    return false;
  }
  std::error_code ec;
  fs::create_directories(path, ec);
  // A path that exists as a file is an error from create_directories in
  // libstdc++; the check below refuses it whatever the library says.
  if (!ec && fs::is_directory(path, ec)) return true;
  if (!ec) {
    *error = path + " exists and is not a folder";
    return false;
  }
  *error = "cannot create " + path + ": " + ec.message();
  return false;
}

}  // namespace tools
