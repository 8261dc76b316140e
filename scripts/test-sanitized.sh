#!/usr/bin/env bash
# scripts/test-sanitized.sh   the whole test suite under AddressSanitizer + UndefinedBehaviorSanitizer,
# the tests whose code runs on several threads under ThreadSanitizer, then a short fuzz run of every
# fuzz target over its kept corpus (when clang is installed).
# Called by test.sh when CI=true (or ATMOGLOBE_SANITIZED_TESTS=1); builds in build-sanitize/,
# build-tsan/ and build-fuzz/, beside the Release build/.
# Build time: both builds go through ccache when it is installed (scripts/install-deps.sh installs
# it), with CCACHE_BASEDIR at the checkout and the build directory left out of the hash, so a fresh
# clone (CI) reuses the objects an earlier clone compiled; -j is the machine's core count (2 on CI).
#
# Sanitized build: GCC (the project's compiler, so the same warnings are errors), -O1 -g1 without
# -DNDEBUG (asserts on), -fno-sanitize-recover=all (every ASan/UBSan report ends the test with a
# failure), warnings as errors. Every test executable, library and tool is built this way, so the
# CLI tests run a sanitized `atmoglobe` too.
# Leaks: detect_leaks=0 for the test suite. The first sanitized CI run failed 44 tests (every GL
# test and every CLI test that renders) on leaks whose stacks end in Mesa llvmpipe's JIT-compiled
# code ("<unknown module>"), which no suppression by library name can match; ASan found no memory
# error and UBSan nothing in that run. Leaks in the readers are still checked: the fuzz run below
# keeps LeakSanitizer on, with scripts/lsan-suppressions.txt (third-party libraries only).
#
# ThreadSanitizer build (build-tsan/): GCC, -DATMOGLOBE_TSAN=ON (-fsanitize=thread -O1 -g1), warnings
# as errors, no GL tests (Mesa llvmpipe is not instrumented: its own threads synchronise through
# code TSan cannot see). Only the test executables of the `threads` label are built (globe, volume,
# map), each from the source files of its threads tests (tests/CMakeLists.txt lists both), and
# `ctest -L threads` runs them with halt_on_error=1: any data race, lock-order inversion or misuse
# of a mutex fails the test. Times: docs/robustness.md, "ThreadSanitizer: the threads tests".
set -euo pipefail
cd "$(dirname "$0")/.."
root="$(pwd)"
seconds="${ATMOGLOBE_FUZZ_SECONDS:-10}"
start=$SECONDS

flags="-O1 -g1"
launcher=()
if command -v ccache >/dev/null 2>&1; then
  launcher=(-DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$root}" CCACHE_NOHASHDIR="${CCACHE_NOHASHDIR:-true}"
fi
if [ ! -f build-sanitize/CMakeCache.txt ]; then
  cmake -S . -B build-sanitize -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    "-DCMAKE_C_FLAGS_RELWITHDEBINFO=$flags" "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=$flags" \
    -DATMOGLOBE_SANITIZE=ON -DATMOGLOBE_WERROR=ON "${launcher[@]}" >/dev/null
fi
cmake --build build-sanitize -j "$(nproc)"
echo "test-sanitized.sh: sanitized build done after $((SECONDS - start)) s"

export ASAN_OPTIONS="detect_leaks=0:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
export LSAN_OPTIONS="suppressions=$root/scripts/lsan-suppressions.txt:print_suppressions=0${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"
(cd build-sanitize && ctest --output-on-failure --timeout 1800 -j "$(nproc)")
echo "test-sanitized.sh: sanitized tests passed after $((SECONDS - start)) s"

if [ ! -f build-tsan/CMakeCache.txt ]; then
  cmake -S . -B build-tsan -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    "-DCMAKE_C_FLAGS_RELWITHDEBINFO=$flags" "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=$flags" \
    -DATMOGLOBE_TSAN=ON -DATMOGLOBE_WERROR=ON -DATMOGLOBE_GL_TESTS=OFF "${launcher[@]}" >/dev/null
fi
cmake --build build-tsan -j "$(nproc)" --target atmoglobe_globe_tests atmoglobe_volume_tests atmoglobe_map_tests
echo "test-sanitized.sh: ThreadSanitizer build done after $((SECONDS - start)) s"
(cd build-tsan &&
  TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1${TSAN_OPTIONS:+:$TSAN_OPTIONS}" \
    ctest -L threads --output-on-failure --timeout 1800 -j "$(nproc)")
echo "test-sanitized.sh: threads tests passed under ThreadSanitizer after $((SECONDS - start)) s"

if command -v clang++ >/dev/null 2>&1; then
  if [ ! -f build-fuzz/CMakeCache.txt ]; then
    cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
      "-DCMAKE_C_FLAGS_RELWITHDEBINFO=$flags" "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=$flags" \
      -DATMOGLOBE_FUZZ=ON -DATMOGLOBE_SANITIZE=ON -DATMOGLOBE_WERROR=ON -DATMOGLOBE_BUILD_TESTS=OFF \
      "${launcher[@]}" >/dev/null
  fi
  cmake --build build-fuzz -j "$(nproc)" --target fuzz
  echo "test-sanitized.sh: fuzz build done after $((SECONDS - start)) s"
  ASAN_OPTIONS=detect_leaks=1 fuzz/run.sh build-fuzz "$seconds"  # leaks checked here (see above)
  echo "test-sanitized.sh: fuzz run (${seconds} s per target) passed after $((SECONDS - start)) s"
else
  echo "test-sanitized.sh: clang++ not installed: no fuzz run (scripts/install-deps.sh installs it)"
fi
