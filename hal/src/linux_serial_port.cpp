#include "hal/linux_serial_port.hpp"

// termios2 and BOTHER come from the kernel's headers; <termios.h> from
// glibc defines a different struct termios, so this file includes only the
// kernel's and calls ioctl directly.
#include <asm/termbits.h>
#include <errno.h>
#include <fcntl.h>
#include <linux/serial.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <time.h>
#include <unistd.h>

#include <cstring>

namespace hal {
namespace detail {
bool set_raw_standard_rate(int fd, std::uint32_t baud);  // linux_serial_termios.cpp
bool flush_input_queue(int fd);                          // linux_serial_termios.cpp
}  // namespace detail

const char* to_string(SerialStatus status) {
  switch (status) {
    case SerialStatus::kOk:
      return "OK";
    case SerialStatus::kTimeout:
      return "TIMEOUT";
    case SerialStatus::kNotOpen:
      return "NOT_OPEN";
    case SerialStatus::kOpenFailed:
      return "OPEN_FAILED";
    case SerialStatus::kConfigFailed:
      return "CONFIG_FAILED";
    case SerialStatus::kIoError:
      return "IO_ERROR";
    case SerialStatus::kEchoMismatch:
      return "ECHO_MISMATCH";
    case SerialStatus::kInvalidArgument:
      return "INVALID_ARGUMENT";
  }
  return "UNKNOWN";
}

LinuxSerialPort::LinuxSerialPort(const Clock* clock) : clock_(clock ? clock : &own_clock_) {}

LinuxSerialPort::~LinuxSerialPort() {
  close();
}

void LinuxSerialPort::close() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

SerialStatus LinuxSerialPort::open(const std::string& path, std::uint32_t baud,
                                   std::string* error) {
  close();
  path_ = path;
  fd_ = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd_ < 0) {
    if (error) *error = path + ": cannot open: " + std::strerror(errno);
    return SerialStatus::kOpenFailed;
  }
  const SerialStatus s = set_baud(baud);
  if (s != SerialStatus::kOk) {
    if (error)
      *error = path + ": cannot set raw 8N1 at " + std::to_string(baud) +
               " baud: " + std::strerror(errno);
    close();
    return s;
  }
  // USB serial adapters (FTDI) batch bytes for up to 16 ms unless told
  // otherwise; a pty or a native UART has no such setting, which is fine.
  struct serial_struct ss;
  if (ioctl(fd_, TIOCGSERIAL, &ss) == 0) {
    ss.flags |= ASYNC_LOW_LATENCY;
    (void)ioctl(fd_, TIOCSSERIAL, &ss);
  }
  return flush_input();
}

SerialStatus LinuxSerialPort::set_baud(std::uint32_t baud) {
  if (fd_ < 0) return SerialStatus::kNotOpen;
  if (baud == 0) return SerialStatus::kInvalidArgument;
  struct termios2 tio;
  if (ioctl(fd_, TCGETS2, &tio) != 0) {
    // No termios2 here: the standard rates through glibc's termios.
    any_baud_ = false;
    if (!detail::set_raw_standard_rate(fd_, baud)) return SerialStatus::kConfigFailed;
    baud_ = baud;
    return SerialStatus::kOk;
  }
  any_baud_ = true;
  // Raw: no line editing, no echo, no signals, no CR/NL translation, no
  // software flow control; 8 data bits, no parity, one stop bit.
  tio.c_iflag = 0;
  tio.c_oflag = 0;
  tio.c_lflag = 0;
  tio.c_cflag = CS8 | CREAD | CLOCAL | BOTHER;
  tio.c_ispeed = baud;
  tio.c_ospeed = baud;
  tio.c_cc[VMIN] = 0;
  tio.c_cc[VTIME] = 0;
  if (ioctl(fd_, TCSETS2, &tio) != 0) return SerialStatus::kConfigFailed;
  baud_ = baud;
  return SerialStatus::kOk;
}

SerialStatus LinuxSerialPort::wait_until(short events, std::int64_t deadline_us) const {
  // Bounded: each pass either returns or waits out the remaining time.
  for (int pass = 0; pass < 1000; ++pass) {
    const std::int64_t left_us = deadline_us - clock_->now_us();
    if (left_us <= 0) return SerialStatus::kTimeout;
    struct pollfd p = {fd_, events, 0};
    struct timespec ts = {static_cast<time_t>(left_us / 1000000),
                          static_cast<long>((left_us % 1000000) * 1000)};
    const int r = ppoll(&p, 1, &ts, nullptr);
    if (r > 0) {
      if (p.revents & events) return SerialStatus::kOk;
      if (p.revents & (POLLERR | POLLHUP | POLLNVAL)) return SerialStatus::kIoError;  // gone
    }
    if (r < 0 && errno != EINTR) return SerialStatus::kIoError;
  }
  return SerialStatus::kTimeout;
}

SerialStatus LinuxSerialPort::write(const std::uint8_t* data, std::size_t n,
                                    std::int64_t timeout_us) {
  if (fd_ < 0) return SerialStatus::kNotOpen;
  if (n > 0 && data == nullptr) return SerialStatus::kInvalidArgument;
  const std::int64_t deadline = clock_->now_us() + timeout_us;
  std::size_t sent = 0;
  while (sent < n) {
    const ssize_t w = ::write(fd_, data + sent, n - sent);
    if (w > 0) {
      sent += static_cast<std::size_t>(w);
      continue;
    }
    if (w < 0 && errno != EAGAIN && errno != EINTR) return SerialStatus::kIoError;
    const SerialStatus s = wait_until(POLLOUT, deadline);
    if (s != SerialStatus::kOk) return s;
  }
  if (!echo_suppression_) return SerialStatus::kOk;
  // Read back exactly what was sent, compared in chunks.
  std::uint8_t echo[64];
  std::size_t checked = 0;
  while (checked < n) {
    const std::size_t want = n - checked < sizeof(echo) ? n - checked : sizeof(echo);
    std::size_t got = 0;
    const SerialStatus s = read(echo, want, want, &got,
                                deadline - clock_->now_us() > 0 ? deadline - clock_->now_us() : 0);
    if (s != SerialStatus::kOk) return s;
    if (std::memcmp(echo, data + checked, got) != 0) return SerialStatus::kEchoMismatch;
    checked += got;
  }
  return SerialStatus::kOk;
}

SerialStatus LinuxSerialPort::read(std::uint8_t* out, std::size_t capacity, std::size_t min_bytes,
                                   std::size_t* n_read, std::int64_t timeout_us) {
  *n_read = 0;
  if (fd_ < 0) return SerialStatus::kNotOpen;
  if (out == nullptr || min_bytes > capacity) return SerialStatus::kInvalidArgument;
  const std::int64_t deadline = clock_->now_us() + timeout_us;
  // Bounded: every pass reads at least a byte, or waits, and the deadline
  // ends the waiting.
  for (std::size_t pass = 0; pass <= 2 * capacity + 2; ++pass) {
    const ssize_t r = ::read(fd_, out + *n_read, capacity - *n_read);
    if (r > 0) {
      *n_read += static_cast<std::size_t>(r);
      if (*n_read >= min_bytes) return SerialStatus::kOk;
      continue;
    }
    // A raw tty (VMIN = VTIME = 0) reads 0 when nothing is there; a device
    // that went away shows as POLLHUP or an error.
    if (r < 0 && errno != EAGAIN && errno != EINTR) return SerialStatus::kIoError;
    if (*n_read >= min_bytes) return SerialStatus::kOk;
    const SerialStatus s = wait_until(POLLIN, deadline);
    if (s != SerialStatus::kOk) return s;
  }
  return SerialStatus::kTimeout;
}

SerialStatus LinuxSerialPort::flush_input() {
  if (fd_ < 0) return SerialStatus::kNotOpen;
  return detail::flush_input_queue(fd_) ? SerialStatus::kOk : SerialStatus::kIoError;
}

}  // namespace hal
