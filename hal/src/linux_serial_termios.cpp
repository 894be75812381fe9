// The fallback for systems without termios2 (some emulators, such as
// qemu-user, do not pass TCGETS2 through): glibc's termios, which knows
// only the standard rates. A separate file because <termios.h> and the
// kernel's <asm/termbits.h> cannot be included together.
#include <termios.h>

#include <cstdint>

namespace hal {
namespace detail {

bool set_raw_standard_rate(int fd, std::uint32_t baud) {
  speed_t speed = 0;
  switch (baud) {
    case 9600:
      speed = B9600;
      break;
    case 19200:
      speed = B19200;
      break;
    case 38400:
      speed = B38400;
      break;
    case 57600:
      speed = B57600;
      break;
    case 115200:
      speed = B115200;
      break;
    case 230400:
      speed = B230400;
      break;
    case 460800:
      speed = B460800;
      break;
    case 500000:
      speed = B500000;
      break;
    case 921600:
      speed = B921600;
      break;
    case 1000000:
      speed = B1000000;
      break;
    case 2000000:
      speed = B2000000;
      break;
    case 3000000:
      speed = B3000000;
      break;
    default:
      return false;
  }
  struct termios t;
  if (tcgetattr(fd, &t) != 0) return false;
  cfmakeraw(&t);
  t.c_cflag |= CLOCAL | CREAD;
  t.c_cc[VMIN] = 0;
  t.c_cc[VTIME] = 0;
  if (cfsetispeed(&t, speed) != 0 || cfsetospeed(&t, speed) != 0) return false;
  return tcsetattr(fd, TCSANOW, &t) == 0;
}

// Through glibc rather than a raw ioctl: a program running under an
// interposing library (umockdev's preload, which the USB camera's
// hardware-in-loop run needs) gets its own ioctl() wrapped, and that
// wrapper fails TCFLSH on a pty; glibc's tcflush goes to the kernel.
bool flush_input_queue(int fd) {
  return tcflush(fd, TCIFLUSH) == 0;
}

}  // namespace detail
}  // namespace hal
