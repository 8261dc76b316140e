#!/usr/bin/env bash
# ./run.sh            install what is missing, build (Release), render the default scene
#                     headless to out/default.png and print its path.
# ./run.sh ARGS...    same set-up, then run `atmoglobe ARGS...` (e.g. ./run.sh view).
set -euo pipefail
cd "$(dirname "$0")"
./scripts/install-deps.sh
./scripts/build.sh atmoglobe default_imagery default_radar default_grid
if [ $# -eq 0 ]; then
  mkdir -p out
  exec build/tools/atmoglobe render -o out/default.png
fi
exec build/tools/atmoglobe "$@"
