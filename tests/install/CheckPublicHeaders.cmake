# ctest install.public_headers (tests/install/CMakeLists.txt): installs the build tree BUILD_DIR's
# Development component (libraries, headers, CMake package) to PREFIX and reads every installed
# header. A header fails when it includes
#  - a header of a private dependency: <netcdf.h>, <hdf5.h>, <H5*.h>, <epoxy/...>, <GL/...>,
#    <EGL/...>, <GLFW/...> (a program using atmoglobe must not need them to compile), or
#  - anything else that is neither <atmoglobe/...> (and installed), <glm/...> (a public dependency)
#    nor a standard C++ header.
# Also checks that <atmoglobe/Version.h> says VERSION.
execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${PREFIX} --component Development
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "cmake --install ${BUILD_DIR} --prefix ${PREFIX} failed (exit ${rc}):\n${out}\n${err}")
endif()

set(include_dir "${PREFIX}/include")
file(GLOB_RECURSE headers RELATIVE "${include_dir}" "${include_dir}/*.h" "${include_dir}/*.hpp")
list(LENGTH headers count)
if(count EQUAL 0)
  message(FATAL_ERROR "no headers installed under ${include_dir}")
endif()

set(private_dependency "^(netcdf\\.h|hdf5\\.h|H5[^/]*\\.h|epoxy/.*|GL/.*|EGL/.*|GLFW/.*)$")
set(problems "")
foreach(header IN LISTS headers)
  file(STRINGS "${include_dir}/${header}" lines REGEX "^[ \t]*#[ \t]*include")
  foreach(line IN LISTS lines)
    if(NOT line MATCHES "#[ \t]*include[ \t]*[<\"]([^>\"]+)[>\"]")
      list(APPEND problems "${header}: ${line}: not an #include <...> this check reads")
      continue()
    endif()
    set(included "${CMAKE_MATCH_1}")
    if(included MATCHES "${private_dependency}")
      list(APPEND problems "${header}: #include <${included}>: a private dependency's header")
    elseif(included MATCHES "^atmoglobe/")
      if(NOT EXISTS "${include_dir}/${included}")
        list(APPEND problems "${header}: #include <${included}>: not installed (a header left out of the install)")
      endif()
    elseif(NOT included MATCHES "^glm/" AND NOT included MATCHES "^[a-z_]+$")
      list(APPEND problems "${header}: #include <${included}>: neither atmoglobe, glm nor the C++ standard library")
    endif()
  endforeach()
endforeach()

file(STRINGS "${include_dir}/atmoglobe/Version.h" version_line REGEX "define ATMOGLOBE_VERSION_STRING")
if(NOT version_line MATCHES "\"${VERSION}\"")
  list(APPEND problems "atmoglobe/Version.h: expected ATMOGLOBE_VERSION_STRING \"${VERSION}\", got: ${version_line}")
endif()

if(problems)
  list(JOIN problems "\n  " text)
  message(FATAL_ERROR "installed public headers under ${include_dir}:\n  ${text}")
endif()
message("${count} installed headers under ${include_dir}: no private dependency's header, every include resolves")
