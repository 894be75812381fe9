# The vendor-SDK lookup of cmake/RoyaleSdk.cmake, run in script mode:
#   cmake -DCASE=missing|no_header|no_library|found -DWORK=<dir> -P check_royale_sdk.cmake
# Each case lays out a folder in WORK the way a user might hand it over
# and runs the lookup on it; CTest matches what it says.
include(${CMAKE_CURRENT_LIST_DIR}/../../cmake/RoyaleSdk.cmake)
set(sdk "${WORK}/royale-sdk-${CASE}")
file(REMOVE_RECURSE "${sdk}")
if(CASE STREQUAL "missing")
  # nothing there
elseif(CASE STREQUAL "no_header")
  file(WRITE "${sdk}/bin/libroyale.so" "")
elseif(CASE STREQUAL "no_library")
  file(WRITE "${sdk}/include/royale.hpp" "")
elseif(CASE STREQUAL "found")
  file(WRITE "${sdk}/include/royale.hpp" "")
  file(WRITE "${sdk}/bin/libroyale.so" "")
else()
  message(FATAL_ERROR "unknown CASE ${CASE}")
endif()
hrp_find_royale_sdk("${sdk}" inc lib)
message(STATUS "royale SDK found: include ${inc}, library ${lib}")
