#!/usr/bin/env bash
# ./test.sh   install what is missing, build (Release) and run every test through ctest.
set -euo pipefail
cd "$(dirname "$0")"
./scripts/install-deps.sh
./scripts/install-validators.sh   # glTF validator (npm) used by the export tests
./scripts/build.sh all
cd build
ctest --output-on-failure --timeout 900 -j "$(nproc)"
