#include "formats/text_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace formats {

const char* to_string(FileStatus status) {
  switch (status) {
    case FileStatus::kOk:
      return "OK";
    case FileStatus::kCannotOpen:
      return "CANNOT_OPEN";
    case FileStatus::kNotRegular:
      return "NOT_REGULAR";
    case FileStatus::kTooLarge:
      return "TOO_LARGE";
    case FileStatus::kReadError:
      return "READ_ERROR";
  }
  return "UNKNOWN";
}

namespace {

std::string megabytes(std::uint64_t bytes) {
  return std::to_string(static_cast<double>(bytes) / (1024.0 * 1024.0)).substr(0, 6) + " MB";
}

}  // namespace

FileStatus read_file_bounded(const std::string& path, std::size_t max_bytes, std::string* out,
                             std::string* error) {
  out->clear();
  // O_NONBLOCK: opening a FIFO for reading would otherwise wait for a writer.
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    *error = path + ": cannot open (" + std::strerror(errno) + ")";
    return FileStatus::kCannotOpen;
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    *error = path + ": not a regular file (" +
             (S_ISDIR(st.st_mode) ? "a folder" : "a device, FIFO or socket") + ")";
    return FileStatus::kNotRegular;
  }
  const auto size = static_cast<std::uint64_t>(st.st_size);
  if (size > max_bytes) {
    ::close(fd);
    *error = path + ": " + megabytes(size) + ", over the limit of " + megabytes(max_bytes) +
             " for this kind of file";
    return FileStatus::kTooLarge;
  }
  out->resize(static_cast<std::size_t>(size));
  std::size_t done = 0;
  // Bounded: each pass reads at least one byte or ends the loop.
  while (done < out->size()) {
    const ssize_t n = ::read(fd, &(*out)[done], out->size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    done += static_cast<std::size_t>(n);
  }
  char extra = 0;
  const bool grew = done == out->size() && ::read(fd, &extra, 1) > 0;
  ::close(fd);
  if (done != out->size() || grew) {
    out->clear();
    *error = path + ": read " + std::to_string(done) + " of " + std::to_string(size) + " bytes (" +
             (grew ? "the file grew while read" : "the read stopped early") + ")";
    return FileStatus::kReadError;
  }
  return FileStatus::kOk;
}

}  // namespace formats
