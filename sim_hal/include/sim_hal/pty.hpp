#pragma once
// A pseudo-terminal for a simulated serial device: the simulator holds the
// master side; any program opens the slave path as it would a USB serial
// adapter, and the real drivers with their termios code run unchanged.
#include <string>

namespace sim_hal {

class PtyDevice {
 public:
  PtyDevice() = default;
  ~PtyDevice();
  PtyDevice(const PtyDevice&) = delete;
  PtyDevice& operator=(const PtyDevice&) = delete;

  // Creates the pair, both sides raw. False with *error on failure.
  bool open(std::string* error);
  void close();
  int master_fd() const { return master_; }
  const std::string& slave_path() const { return slave_path_; }

 private:
  int master_ = -1;
  // The simulator keeps the slave open too, so that the master does not
  // see a hang-up each time a client closes the device.
  int slave_keepalive_ = -1;
  std::string slave_path_;
};

}  // namespace sim_hal
