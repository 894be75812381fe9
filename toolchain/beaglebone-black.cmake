# BeagleBone Black: TI AM335x, ARM Cortex-A8 with NEON, hard-float ABI.
# Included through CMAKE_PROJECT_INCLUDE in the armhf preset, after the
# toolchain file, so the flags reach every target and try_compile.
set(HRP_BOARD_FLAGS "-mcpu=cortex-a8 -mfpu=neon -mfloat-abi=hard")
string(APPEND CMAKE_C_FLAGS " ${HRP_BOARD_FLAGS}")
string(APPEND CMAKE_CXX_FLAGS " ${HRP_BOARD_FLAGS}")
# GCC notes that the ARM ABI for passing some structs changed in GCC 7.1;
# everything here is built with GCC 12, so the note says nothing to us.
string(APPEND CMAKE_CXX_FLAGS " -Wno-psabi")
# 64-bit file offsets and directory cookies on this 32-bit target: without
# them glibc's readdir() fails with EOVERFLOW on a filesystem whose
# directory offsets need 64 bits (ext4's hashed directories; seen under
# qemu-arm here, where a folder of recorded frames read as empty), and
# files over 2 GB (LCM logs of long runs) cannot be written.
string(APPEND CMAKE_C_FLAGS " -D_FILE_OFFSET_BITS=64")
string(APPEND CMAKE_CXX_FLAGS " -D_FILE_OFFSET_BITS=64")
