#!/usr/bin/env bash
# scripts/build.sh TARGET...   configure (once) and build the given targets in build/ (Release).
# Warnings are errors when CI=true.
set -euo pipefail
cd "$(dirname "$0")/.."
werror=OFF
if [ "${CI:-}" = "true" ]; then werror=ON; fi
# ccache when installed (scripts/install-deps.sh installs it), as in scripts/test-sanitized.sh:
# CCACHE_BASEDIR at the checkout, the build directory out of the hash, so a fresh clone (CI)
# reuses what an earlier clone compiled.
launcher=()
if command -v ccache >/dev/null 2>&1; then
  launcher=(-DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$(pwd)}" CCACHE_NOHASHDIR="${CCACHE_NOHASHDIR:-true}"
fi
if [ ! -f build/CMakeCache.txt ] || ! grep -q "ATMOGLOBE_WERROR:BOOL=${werror}" build/CMakeCache.txt; then
  cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DATMOGLOBE_WERROR=${werror} "${launcher[@]}" >/dev/null
fi
targets=()
for t in "$@"; do targets+=(--target "$t"); done
cmake --build build -j "$(nproc)" "${targets[@]}"
