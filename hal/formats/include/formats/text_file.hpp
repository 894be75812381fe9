#pragma once
// Reading a whole file into memory with its size known and bounded first:
// a configuration, scenario or frame must be a regular file no larger than
// the caller's limit, so that /dev/zero, a FIFO or a runaway file is
// refused by name instead of filling the robot's 512 MB.
#include <cstddef>
#include <cstdint>
#include <string>

namespace formats {

enum class FileStatus : std::uint8_t {
  kOk,
  kCannotOpen,  // missing, or no permission
  kNotRegular,  // a folder, FIFO, device or socket
  kTooLarge,    // over the caller's limit
  kReadError,   // the read failed or the file changed size while read
};
const char* to_string(FileStatus status);

// Configuration, scenario and summary files: the largest shipped is a few
// kB; 4 MB is generous for a hand-written file and, parsed, stays well
// inside the board's 512 MB.
constexpr std::size_t kMaxTextFileBytes = 4u << 20;

// Reads the whole of `path` into *out. On failure *error is
// "PATH: what is wrong" and *out is empty.
FileStatus read_file_bounded(const std::string& path, std::size_t max_bytes, std::string* out,
                             std::string* error);

}  // namespace formats
