# Installing atmoglobe as a library: `cmake --install build --prefix P` gives
#   P/lib/libatmoglobe_{globe,io,volume,map,engine}.a   (the shaders are compiled into the engine's; io's headers are not installed)
#   P/include/atmoglobe/{globe,volume,map,engine}/*.h, P/include/atmoglobe/Version.h
#   P/lib/cmake/atmoglobe/atmoglobe{Config,ConfigVersion,Targets}.cmake
#   P/bin/atmoglobe
# so that a program can `find_package(atmoglobe 0.1 REQUIRED)` and link atmoglobe::engine
# (examples/). The package's files: cmake/atmoglobeConfig.cmake.in.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(ATMOGLOBE_INSTALL_CMAKEDIR "${CMAKE_INSTALL_LIBDIR}/cmake/atmoglobe")

# atmoglobe_public_headers(<target> [EXCLUDE <file name>...])
# The headers under <folder>/include/ become <target>'s public header set: on the include path of
# its users in the build tree and installed under P/include. Files named in EXCLUDE stay usable
# inside the build (tools, tests) but are not installed, so no installed header may include them
# (the ctest install.public_headers checks that every installed #include <atmoglobe/...> resolves).
function(atmoglobe_public_headers target)
  cmake_parse_arguments(ARG "" "" "EXCLUDE" ${ARGN})
  set(base "${CMAKE_CURRENT_SOURCE_DIR}/include")
  file(GLOB_RECURSE headers CONFIGURE_DEPENDS "${base}/*.h")
  foreach(name IN LISTS ARG_EXCLUDE)
    list(FILTER headers EXCLUDE REGEX "/${name}$")
  endforeach()
  target_sources(${target} PUBLIC FILE_SET HEADERS BASE_DIRS "${base}" FILES ${headers})
endfunction()

# atmoglobe_install(LIBRARIES <target>... PROGRAMS <target>...)
# LIBRARIES: the export set, exported as atmoglobe::<name without the atmoglobe_ prefix> with the
# project VERSION. A static library links its private dependencies through its users, so every
# library an exported one links must be in the set, private ones too: a private static library
# joins with one more name in LIBRARIES. Its include directories must then name the source tree
# only inside $<BUILD_INTERFACE:...> (an exported target cannot point into the source tree), e.g.
#   target_include_directories(atmoglobe_io PUBLIC $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>)
# and, having no public header set, it installs its archive and no headers.
# PROGRAMS: executables installed to P/bin.
function(atmoglobe_install)
  cmake_parse_arguments(ARG "" "" "LIBRARIES;PROGRAMS" ${ARGN})
  foreach(target IN LISTS ARG_LIBRARIES)
    string(REGEX REPLACE "^atmoglobe_" "" name "${target}")
    # VERSION names no file of a static library; it says which release the target is.
    set_target_properties(${target} PROPERTIES EXPORT_NAME "${name}" VERSION "${PROJECT_VERSION}")
  endforeach()
  install(TARGETS ${ARG_LIBRARIES} EXPORT atmoglobeTargets
          ARCHIVE DESTINATION "${CMAKE_INSTALL_LIBDIR}" COMPONENT Development
          FILE_SET HEADERS DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}" COMPONENT Development)
  install(EXPORT atmoglobeTargets NAMESPACE atmoglobe:: DESTINATION "${ATMOGLOBE_INSTALL_CMAKEDIR}"
          COMPONENT Development)
  install(TARGETS ${ARG_PROGRAMS} RUNTIME DESTINATION "${CMAKE_INSTALL_BINDIR}" COMPONENT Runtime)

  set(gen "${CMAKE_BINARY_DIR}/generated/cmake")
  configure_package_config_file("${PROJECT_SOURCE_DIR}/cmake/atmoglobeConfig.cmake.in" "${gen}/atmoglobeConfig.cmake"
                                INSTALL_DESTINATION "${ATMOGLOBE_INSTALL_CMAKEDIR}")
  # SameMinorVersion while the major version is 0: before 1.0 a minor release may change the API
  # (semver: "anything may change at any time"), so a program written against 0.1 accepts 0.1.x
  # (x >= the one it asks for) and not 0.2. SameMajorVersion would accept every 0.y. From 1.0 on,
  # SameMajorVersion.
  if(PROJECT_VERSION_MAJOR EQUAL 0)
    set(compatibility SameMinorVersion)
  else()
    set(compatibility SameMajorVersion)
  endif()
  write_basic_package_version_file("${gen}/atmoglobeConfigVersion.cmake" VERSION "${PROJECT_VERSION}"
                                   COMPATIBILITY ${compatibility})
  install(FILES "${gen}/atmoglobeConfig.cmake" "${gen}/atmoglobeConfigVersion.cmake"
          DESTINATION "${ATMOGLOBE_INSTALL_CMAKEDIR}" COMPONENT Development)
endfunction()
