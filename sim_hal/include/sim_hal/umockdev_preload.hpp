#pragma once
// A program with an emulated USB device (tests, fsw_app --camera usb) must
// run under umockdev's preload library, the process that owns the testbed
// included (it alone would not see hotplug events otherwise). CTest and
// users start them plainly: this re-executes the program with the library
// preloaded, and with AddressSanitizer told not to insist on being first in
// the library order.
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace sim_hal {
namespace umockdev_preload {

constexpr const char* kLibrary = "libumockdev-preload.so.0";

// Returns only when already preloaded; otherwise replaces the process (or
// exits 1 with the reason).
inline void ensure(char** argv) {
  const char* preload = std::getenv("LD_PRELOAD");
  if (preload != nullptr && std::strstr(preload, "libumockdev-preload") != nullptr) return;
  std::string value = kLibrary;
  if (preload != nullptr && preload[0] != '\0') value += std::string(":") + preload;
  setenv("LD_PRELOAD", value.c_str(), 1);
  std::string asan = "verify_asan_link_order=0";
  if (const char* old = std::getenv("ASAN_OPTIONS")) asan += std::string(":") + old;
  setenv("ASAN_OPTIONS", asan.c_str(), 1);
  execv("/proc/self/exe", argv);
  std::fprintf(stderr, "re-executing %s under %s: %s\n", argv[0], kLibrary, std::strerror(errno));
  std::exit(1);
}

}  // namespace umockdev_preload
}  // namespace sim_hal
