# The arrows of the house point one way: fsw_app uses estimator, arm,
# drivers and hal; tools sits on top of everything. A file that includes a
# header from a layer above its own fails this test, naming file and line.
#   cmake -DROOT=<source dir> -P tests/layering.cmake
set(rules
  # folder           headers it must not include
  "hal|estimator/ arm/ arm_io/ dynamixel/ gripper/ pico_flexx/ royale/ fsw_app/ sim_hal/ tools/"
  "estimator|arm/ arm_io/ dynamixel/ gripper/ pico_flexx/ fsw_app/ sim_hal/ tools/"
  "arm|estimator/ fsw_app/ sim_hal/ tools/"
  "drivers|estimator/ fsw_app/ sim_hal/ tools/"
  "fsw_app/src|tools/"
  "fsw_app/include|tools/"
  "sim_hal|fsw_app/ tools/")
set(bad "")
foreach(rule ${rules})
  string(REPLACE "|" ";" parts "${rule}")
  list(GET parts 0 folder)
  list(GET parts 1 forbidden)
  string(REPLACE " " ";" forbidden "${forbidden}")
  file(GLOB_RECURSE files "${ROOT}/${folder}/*.hpp" "${ROOT}/${folder}/*.cpp" "${ROOT}/${folder}/*.h"
       "${ROOT}/${folder}/*.c")
  foreach(f ${files})
    file(STRINGS "${f}" lines REGEX "^[ \t]*#[ \t]*include[ \t]*\"")
    foreach(line ${lines})
      foreach(prefix ${forbidden})
        if(line MATCHES "#[ \t]*include[ \t]*\"${prefix}")
          file(RELATIVE_PATH rel "${ROOT}" "${f}")
          string(APPEND bad "  ${rel}: ${line} (${folder} must not include ${prefix})\n")
        endif()
      endforeach()
    endforeach()
  endforeach()
endforeach()
if(bad)
  message(FATAL_ERROR "layering: headers from a layer above:\n${bad}")
endif()
message(STATUS "layering: every include points down")
