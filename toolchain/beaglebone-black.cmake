# BeagleBone Black: TI AM335x, ARM Cortex-A8 with NEON, hard-float ABI.
# Included through CMAKE_PROJECT_INCLUDE in the armhf preset, after the
# toolchain file, so the flags reach every target and try_compile.
set(HRP_BOARD_FLAGS "-mcpu=cortex-a8 -mfpu=neon -mfloat-abi=hard")
string(APPEND CMAKE_C_FLAGS " ${HRP_BOARD_FLAGS}")
string(APPEND CMAKE_CXX_FLAGS " ${HRP_BOARD_FLAGS}")
# GCC notes that the ARM ABI for passing some structs changed in GCC 7.1;
# everything here is built with GCC 12, so the note says nothing to us.
string(APPEND CMAKE_CXX_FLAGS " -Wno-psabi")
