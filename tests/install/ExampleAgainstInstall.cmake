# ctest install.example_radar_to_png (tests/install/CMakeLists.txt): what a user does with the
# package, in one script.
#  1. cmake --install BUILD_DIR --prefix PREFIX (PREFIX emptied first, so nothing stale hides a
#     file the install misses);
#  2. configure and build EXAMPLE_DIR in WORK/build against it: CMAKE_PREFIX_PATH=PREFIX and the
#     example's own find_package(atmoglobe 0.1 REQUIRED); compiler CXX_COMPILER through LAUNCHER
#     (ccache) when given, with FLAGS for compiling and linking (a sanitized build's);
#  3. run it on RADAR (the SYNTHETIC volume the build writes): exit 0, the site and the gate's
#     position printed, a PNG written, at least MIN_PIXELS pixels drawn by the radar;
#  4. run it with no argument (usage, exit 2) and on a file that is no radar volume (exit 1, the
#     message naming the file, no PNG).
function(run_step what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "install test: ${what} failed (exit ${rc}):\n${out}\n${err}")
  endif()
  set(step_output "${out}" PARENT_SCOPE)
  set(step_error "${err}" PARENT_SCOPE)
endfunction()

if(NOT EXISTS "${RADAR}")
  message(FATAL_ERROR "install test: the synthetic radar volume ${RADAR} is missing (the build's default_radar "
                      "target writes it: cmake --build ${BUILD_DIR})")
endif()
file(REMOVE_RECURSE "${PREFIX}" "${WORK}/build")

run_step("cmake --install ${BUILD_DIR} --prefix ${PREFIX}" ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${PREFIX})
set(configure -S ${EXAMPLE_DIR} -B ${WORK}/build -DCMAKE_PREFIX_PATH=${PREFIX} -DCMAKE_BUILD_TYPE=Release
              -DCMAKE_CXX_COMPILER=${CXX_COMPILER})
if(LAUNCHER)
  list(APPEND configure -DCMAKE_CXX_COMPILER_LAUNCHER=${LAUNCHER})
endif()
if(FLAGS)
  list(APPEND configure "-DCMAKE_CXX_FLAGS=${FLAGS}" "-DCMAKE_EXE_LINKER_FLAGS=${FLAGS}")
endif()
run_step("configuring ${EXAMPLE_DIR} against ${PREFIX} (find_package(atmoglobe))" ${CMAKE_COMMAND} ${configure})
run_step("building ${EXAMPLE_DIR} against ${PREFIX}" ${CMAKE_COMMAND} --build ${WORK}/build)

set(example ${WORK}/build/radar_to_png)
set(png ${WORK}/radar.png)
file(REMOVE ${png})
run_step("running ${example} ${RADAR} ${png}" ${example} ${RADAR} ${png})
message("${step_output}${step_error}")
foreach(expected "site [^:]*: lat -?[0-9.]+ deg, lon -?[0-9.]+ deg"
                 "sweep 0 ray 0 gate [0-9]+ .*: lat -?[0-9.]+ deg, lon -?[0-9.]+ deg, height -?[0-9.]+ m")
  if(NOT step_output MATCHES "${expected}")
    message(FATAL_ERROR "install test: the example's output does not match \"${expected}\"")
  endif()
endforeach()
if(NOT EXISTS ${png})
  message(FATAL_ERROR "install test: the example wrote no ${png}")
endif()
file(READ ${png} signature LIMIT 8 HEX)
file(SIZE ${png} size)
if(NOT signature STREQUAL "89504e470d0a1a0a" OR size EQUAL 0)
  message(FATAL_ERROR "install test: ${png} is not a PNG (${size} bytes, starts ${signature})")
endif()
if(NOT step_output MATCHES "([0-9]+) pixels drawn by the radar")
  message(FATAL_ERROR "install test: the example did not say how many pixels the radar drew")
endif()
if(CMAKE_MATCH_1 LESS MIN_PIXELS)
  message(FATAL_ERROR "install test: the radar drew ${CMAKE_MATCH_1} pixels of ${png}, expected at least ${MIN_PIXELS}")
endif()

execute_process(COMMAND ${example} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 2 OR NOT err MATCHES "usage: radar_to_png RADAR_FILE")
  message(FATAL_ERROR "install test: with no argument the example should print its usage and exit 2; exit ${rc}:\n${out}${err}")
endif()
set(bad ${EXAMPLE_DIR}/CMakeLists.txt)
file(REMOVE ${WORK}/bad.png)
execute_process(COMMAND ${example} ${bad} ${WORK}/bad.png RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 1 OR NOT err MATCHES "^radar_to_png: [^\n]*CMakeLists.txt" OR EXISTS ${WORK}/bad.png)
  message(FATAL_ERROR "install test: on a file that is no radar volume the example should exit 1 naming it, "
                      "writing nothing; exit ${rc}:\n${out}${err}")
endif()
message("install test: ${example} built against ${PREFIX}; ${png} (${size} bytes); bad input: ${err}")
