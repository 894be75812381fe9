# BeagleBone Black: TI AM335x, ARM Cortex-A8 with NEON, hard-float ABI.
# Included through CMAKE_PROJECT_INCLUDE in the armhf preset, after the
# toolchain file, so the flags reach every target and try_compile.
set(HRP_BOARD_FLAGS "-mcpu=cortex-a8 -mfpu=neon -mfloat-abi=hard")
string(APPEND CMAKE_C_FLAGS " ${HRP_BOARD_FLAGS}")
string(APPEND CMAKE_CXX_FLAGS " ${HRP_BOARD_FLAGS}")
