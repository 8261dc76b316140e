# One function configures every target: language standard, warnings, sanitizers.
# No -ffast-math anywhere: geodesy and volume maths rely on IEEE semantics.
#
# ATMOGLOBE_SANITIZE: AddressSanitizer + UndefinedBehaviorSanitizer, every finding fatal
# (-fno-sanitize-recover=all: a UB report fails the test instead of scrolling past). The build that
# runs the test suite under them (scripts/test-sanitized.sh) also keeps asserts on.
# ATMOGLOBE_FUZZ (clang only): libFuzzer coverage instrumentation of every target, and the fuzz
# targets of fuzz/ (fuzz/README.md).
# ATMOGLOBE_TSAN: ThreadSanitizer (-fsanitize=thread, -O1 -g1, frame pointers) for the tests that
# start threads (ctest label `threads`; scripts/test-sanitized.sh builds only those). It cannot be
# combined with AddressSanitizer, hence its own option and its own build directory.
option(ATMOGLOBE_TSAN "Build with ThreadSanitizer (the threads tests: scripts/test-sanitized.sh)" OFF)
if(ATMOGLOBE_TSAN AND ATMOGLOBE_SANITIZE)
  message(FATAL_ERROR "ATMOGLOBE_TSAN and ATMOGLOBE_SANITIZE exclude each other (ThreadSanitizer cannot run with "
                      "AddressSanitizer): configure a separate build directory for each")
endif()

function(atmoglobe_configure_target target)
  target_compile_features(${target} PUBLIC cxx_std_20)
  set_target_properties(${target} PROPERTIES CXX_EXTENSIONS OFF)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wshadow -Wconversion -Wno-sign-conversion)
  if(ATMOGLOBE_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
  if(ATMOGLOBE_SANITIZE)
    target_compile_options(${target} PRIVATE -fsanitize=address,undefined -fno-sanitize-recover=all
                                             -fno-omit-frame-pointer)
    target_link_options(${target} PRIVATE -fsanitize=address,undefined -fno-sanitize-recover=all)
    # GCC 12's -Wmaybe-uninitialized is unreliable with the sanitizers' instrumentation (GCC's
    # manual says so for -fsanitize=address): it reported std::function members inside
    # libstdc++'s <regex> as uninitialized (NrrdExportTest.cpp), code the Release build compiles
    # without a warning. Only that warning is dropped, only in this build.
    if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
      target_compile_options(${target} PRIVATE -Wno-maybe-uninitialized)
    endif()
  endif()
  if(ATMOGLOBE_TSAN)
    # -O1 -g1 after the build type's flags: the optimisation TSan's reports stay readable at.
    target_compile_options(${target} PRIVATE -fsanitize=thread -O1 -g1 -fno-omit-frame-pointer)
    target_link_options(${target} PRIVATE -fsanitize=thread)
  endif()
  if(ATMOGLOBE_FUZZ)
    target_compile_options(${target} PRIVATE -fsanitize=fuzzer-no-link)
  endif()
endfunction()
