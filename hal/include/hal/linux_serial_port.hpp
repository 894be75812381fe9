#pragma once
// SerialPort on Linux termios: raw 8N1, any baud rate (termios2 with BOTHER,
// so 1 Mbps and non-standard rates work), non-blocking I/O waited on with
// ppoll against a monotonic deadline. The port is chosen at run time by a
// path: a device (/dev/ttyUSB0, /dev/ttyO1) or a pseudo-terminal.
#include <string>

#include "hal/clock.hpp"
#include "hal/serial_port.hpp"

namespace hal {

class LinuxSerialPort final : public SerialPort {
 public:
  // The clock sets deadlines; null means the process's monotonic clock.
  explicit LinuxSerialPort(const Clock* clock = nullptr);
  ~LinuxSerialPort() override;
  LinuxSerialPort(const LinuxSerialPort&) = delete;
  LinuxSerialPort& operator=(const LinuxSerialPort&) = delete;

  // Opens and configures the port; *error (when given) names the path and
  // the system's reason on failure.
  SerialStatus open(const std::string& path, std::uint32_t baud, std::string* error = nullptr);
  void close();
  bool is_open() const { return fd_ >= 0; }
  const std::string& path() const { return path_; }

  SerialStatus write(const std::uint8_t* data, std::size_t n, std::int64_t timeout_us) override;
  SerialStatus read(std::uint8_t* out, std::size_t capacity, std::size_t min_bytes,
                    std::size_t* n_read, std::int64_t timeout_us) override;
  SerialStatus flush_input() override;
  SerialStatus set_baud(std::uint32_t baud) override;
  std::uint32_t baud() const override { return baud_; }
  void set_echo_suppression(bool on) override { echo_suppression_ = on; }
  // False where the kernel interface for arbitrary rates (termios2) is
  // missing, as under qemu-user: then only the standard rates open.
  bool any_baud_supported() const { return any_baud_; }

 private:
  // Waits until the descriptor is readable (or writable): kOk, kTimeout at
  // the deadline, kIoError when the device went away.
  SerialStatus wait_until(short events, std::int64_t deadline_us) const;

  MonotonicClock own_clock_;
  const Clock* clock_;
  int fd_ = -1;
  std::uint32_t baud_ = 0;
  bool echo_suppression_ = false;
  bool any_baud_ = true;
  std::string path_;
};

}  // namespace hal
