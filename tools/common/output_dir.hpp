#pragma once
// The folder a tool writes its output into (--out, --debug-png, -o),
// created with any missing parents, as `mkdir -p` would: a user asking for
// hreval-out/today/ should not have to make hreval-out/ first.
#include <string>

namespace tools {

// True when `path` is a directory afterwards. Otherwise false, and *error
// names the path and what stood in the way (a file where a folder should
// be, no permission, ...).
bool make_output_dir(const std::string& path, std::string* error);

}  // namespace tools
