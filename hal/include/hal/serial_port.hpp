#pragma once
// A byte stream to a device: the Dynamixel bus and the gripper board each
// talk through one. The Linux implementation is termios on a device path or
// a pseudo-terminal; tests and the simulator use it unchanged on ptys.
#include <cstddef>
#include <cstdint>

namespace hal {

enum class SerialStatus : std::uint8_t {
  kOk,
  kTimeout,       // fewer bytes than asked for arrived in time
  kNotOpen,       // no open port
  kOpenFailed,    // the path could not be opened
  kConfigFailed,  // the line settings (raw 8N1, baud rate) were refused
  kIoError,       // read or write failed, or the device went away
  kEchoMismatch,  // echo suppression read back bytes other than those sent
  kInvalidArgument,
};
const char* to_string(SerialStatus status);

class SerialPort {
 public:
  virtual ~SerialPort() = default;

  // Sends all n bytes within the timeout. With echo suppression on (a
  // half-duplex adapter that hears itself), then reads back exactly n bytes
  // and checks that they are the ones sent.
  virtual SerialStatus write(const std::uint8_t* data, std::size_t n, std::int64_t timeout_us) = 0;

  // Reads what arrives, up to `capacity` bytes, returning as soon as at
  // least `min_bytes` have come (or the timeout passes: kTimeout, with
  // *n_read saying how many did come).
  virtual SerialStatus read(std::uint8_t* out, std::size_t capacity, std::size_t min_bytes,
                            std::size_t* n_read, std::int64_t timeout_us) = 0;

  // Drops whatever was received and not yet read.
  virtual SerialStatus flush_input() = 0;

  virtual SerialStatus set_baud(std::uint32_t baud) = 0;
  virtual std::uint32_t baud() const = 0;
  virtual void set_echo_suppression(bool on) = 0;
};

}  // namespace hal
