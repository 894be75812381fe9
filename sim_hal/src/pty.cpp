#include "sim_hal/pty.hpp"

#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <termios.h>
#include <unistd.h>

#include <cstring>

namespace sim_hal {
namespace {
bool make_raw(int fd) {
  struct termios t;
  if (tcgetattr(fd, &t) != 0) return false;
  cfmakeraw(&t);
  return tcsetattr(fd, TCSANOW, &t) == 0;
}
}  // namespace

PtyDevice::~PtyDevice() {
  close();
}

void PtyDevice::close() {
  if (slave_keepalive_ >= 0) ::close(slave_keepalive_);
  if (master_ >= 0) ::close(master_);
  slave_keepalive_ = master_ = -1;
}

bool PtyDevice::open(std::string* error) {
  close();
  master_ = posix_openpt(O_RDWR | O_NOCTTY | O_CLOEXEC);
  if (master_ < 0 || grantpt(master_) != 0 || unlockpt(master_) != 0) {
    *error = std::string("cannot create a pseudo-terminal: ") + std::strerror(errno);
    close();
    return false;
  }
  char name[128];
  if (ptsname_r(master_, name, sizeof(name)) != 0) {
    *error = std::string("cannot name the pseudo-terminal: ") + std::strerror(errno);
    close();
    return false;
  }
  slave_path_ = name;
  slave_keepalive_ = ::open(name, O_RDWR | O_NOCTTY | O_CLOEXEC);
  // Raw both ways before any client arrives: no echo, no CR/NL mapping.
  if (slave_keepalive_ < 0 || !make_raw(slave_keepalive_) || !make_raw(master_)) {
    *error = slave_path_ + ": cannot set raw mode: " + std::strerror(errno);
    close();
    return false;
  }
  const int flags = fcntl(master_, F_GETFL);
  fcntl(master_, F_SETFL, flags | O_NONBLOCK);
  return true;
}

}  // namespace sim_hal
