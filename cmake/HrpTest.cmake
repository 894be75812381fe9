# hrp_add_test(NAME name SOURCES ... LIBS ...)
# One CMocka executable registered with CTest. When cross compiling, CTest
# runs it through CMAKE_CROSSCOMPILING_EMULATOR (qemu-arm with the sysroot).
function(hrp_add_test)
  cmake_parse_arguments(T "" "NAME;TIMEOUT" "SOURCES;LIBS;ARGS" ${ARGN})
  add_executable(${T_NAME} ${T_SOURCES})
  target_link_libraries(${T_NAME} PRIVATE ${T_LIBS} PkgConfig::CMOCKA hrp_warnings)
  target_include_directories(${T_NAME} PRIVATE ${PROJECT_SOURCE_DIR}/tests/support)
  add_test(NAME ${T_NAME} COMMAND ${T_NAME} ${T_ARGS})
  if(NOT T_TIMEOUT)
    set(T_TIMEOUT 120)
  endif()
  set_tests_properties(${T_NAME} PROPERTIES TIMEOUT ${T_TIMEOUT}
    ENVIRONMENT "HRP_SOURCE_DIR=${PROJECT_SOURCE_DIR}")
endfunction()
