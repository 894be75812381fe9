# Cross toolchain: Debian's arm-linux-gnueabihf GCC and an armhf sysroot.
# Tools and sysroot only; CPU flags for the board are in beaglebone-black.cmake.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR armv7l)

set(CMAKE_C_COMPILER arm-linux-gnueabihf-gcc)
set(CMAKE_CXX_COMPILER arm-linux-gnueabihf-g++)

if(NOT HRP_SYSROOT)
  if(DEFINED ENV{HRP_SYSROOT})
    set(HRP_SYSROOT "$ENV{HRP_SYSROOT}")
  else()
    set(HRP_SYSROOT "$ENV{HOME}/.cache/hrp/sysroot-armhf-bookworm")
  endif()
endif()
if(NOT EXISTS "${HRP_SYSROOT}/usr/include")
  message(FATAL_ERROR "armhf sysroot not found at ${HRP_SYSROOT}: run toolchain/make-sysroot")
endif()
set(CMAKE_SYSROOT "${HRP_SYSROOT}")
# Let try_compile see the sysroot location too.
list(APPEND CMAKE_TRY_COMPILE_PLATFORM_VARIABLES HRP_SYSROOT)

set(CMAKE_FIND_ROOT_PATH "${HRP_SYSROOT}")
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)

# pkg-config must read the sysroot's .pc files, not the host's.
set(ENV{PKG_CONFIG_DIR} "")
set(ENV{PKG_CONFIG_LIBDIR} "${HRP_SYSROOT}/usr/lib/arm-linux-gnueabihf/pkgconfig:${HRP_SYSROOT}/usr/share/pkgconfig")
set(ENV{PKG_CONFIG_SYSROOT_DIR} "${HRP_SYSROOT}")

# Robot binaries' tests run under user-mode qemu with the sysroot's loader.
set(CMAKE_CROSSCOMPILING_EMULATOR qemu-arm -L "${HRP_SYSROOT}")
