#include "frame_receive_buffer.hpp"

#include <cstdio>

namespace fsw_app {

bool with_frame_receive_buffer(std::string* url, std::string* error) {
  constexpr long kWantedBytes = 4L << 20;
  if (url->rfind("udpm://", 0) != 0 || url->find("recv_buf_size=") != std::string::npos) {
    return true;
  }
  long rmem_max = -1;
  if (std::FILE* f = std::fopen("/proc/sys/net/core/rmem_max", "r")) {
    if (std::fscanf(f, "%ld", &rmem_max) != 1) rmem_max = -1;
    std::fclose(f);
  }
  *url += (url->find('?') == std::string::npos ? "?" : "&") + std::string("recv_buf_size=") +
          std::to_string(kWantedBytes);
  if (rmem_max >= 0 && rmem_max < kWantedBytes) {
    *error = "depth frames over udpm want a 4 MB receive buffer but the kernel allows " +
             std::to_string(rmem_max) + " bytes, so frames would be lost: sudo sysctl -w " +
             "net.core.rmem_max=" + std::to_string(kWantedBytes);
    return false;
  }
  return true;
}

}  // namespace fsw_app
