# Which royale the royale-API code builds against (hal::DepthCamera on
# royale, drivers/pico_flexx/royale_hal):
#   HRP_ROYALE_SDK_DIR empty (default)  the project's royale API on its own
#                                       Pico Flexx driver (pico_flexx_royale)
#   HRP_ROYALE_SDK_DIR=<folder>         the vendor's royale SDK unpacked in
#                                       <folder>: include/royale.hpp and
#                                       bin/ (or lib/) libroyale.so
# The lookup is a function of its own so that a script-mode test can run it.
set(HRP_ROYALE_SDK_DIR "" CACHE PATH
  "The vendor's royale SDK folder (include/royale.hpp, bin/libroyale.so); empty: the project's royale API")

# Sets <include_var> and <library_var> to the SDK's include folder and
# library, or stops the configuration saying what is missing and what to do.
function(hrp_find_royale_sdk sdk_dir include_var library_var)
  if(NOT IS_DIRECTORY "${sdk_dir}")
    message(FATAL_ERROR "HRP_ROYALE_SDK_DIR=${sdk_dir} is not a folder: give the folder the "
      "royale SDK was unpacked into (it holds include/royale.hpp), or leave HRP_ROYALE_SDK_DIR "
      "empty to build on the project's royale API")
  endif()
  if(NOT EXISTS "${sdk_dir}/include/royale.hpp")
    message(FATAL_ERROR "HRP_ROYALE_SDK_DIR=${sdk_dir} has no include/royale.hpp: give the SDK's "
      "top folder (the one with include/ and bin/), not a subfolder")
  endif()
  find_library(_hrp_royale_library NAMES royale
    PATHS "${sdk_dir}/bin" "${sdk_dir}/lib" NO_DEFAULT_PATH NO_CACHE)
  if(NOT _hrp_royale_library)
    message(FATAL_ERROR "HRP_ROYALE_SDK_DIR=${sdk_dir} has include/royale.hpp but no libroyale "
      "in bin/ or lib/: is it the SDK for this machine's architecture (armhf on the BeagleBone)?")
  endif()
  set(${include_var} "${sdk_dir}/include" PARENT_SCOPE)
  set(${library_var} "${_hrp_royale_library}" PARENT_SCOPE)
endfunction()

# Target royale_api: what the royale-API code links.
function(hrp_add_royale_api)
  if(HRP_ROYALE_SDK_DIR)
    hrp_find_royale_sdk("${HRP_ROYALE_SDK_DIR}" inc lib)
    add_library(royale_api SHARED IMPORTED GLOBAL)
    set_target_properties(royale_api PROPERTIES IMPORTED_LOCATION "${lib}"
      INTERFACE_INCLUDE_DIRECTORIES "${inc}")
    message(STATUS "royale API: the vendor's SDK, ${lib}")
  else()
    add_library(royale_api INTERFACE)
    target_link_libraries(royale_api INTERFACE pico_flexx_royale)
    message(STATUS "royale API: the project's (pico_flexx_royale)")
  endif()
endfunction()
