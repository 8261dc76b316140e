#!/usr/bin/env bash
# scripts/build.sh TARGET...   configure (once) and build the given targets in build/ (Release).
# Warnings are errors when CI=true.
set -euo pipefail
cd "$(dirname "$0")/.."
werror=OFF
if [ "${CI:-}" = "true" ]; then werror=ON; fi
if [ ! -f build/CMakeCache.txt ] || ! grep -q "ATMOGLOBE_WERROR:BOOL=${werror}" build/CMakeCache.txt; then
  cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DATMOGLOBE_WERROR=${werror} >/dev/null
fi
targets=()
for t in "$@"; do targets+=(--target "$t"); done
cmake --build build -j "$(nproc)" "${targets[@]}"
