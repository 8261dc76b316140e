#!/usr/bin/env bash
# Copies the images the golden-image test last rendered over the reviewed ones.
# Look at them first (build/test-output/<test>-<pid>/*.actual.png and *.diff.png; a run
# whose tests all passed removes its directory: ATMOGLOBE_KEEP_TEST_OUTPUT=1 keeps it).
set -euo pipefail
cd "$(dirname "$0")/.."
for f in build/test-output/*/*.actual.png; do
  name=$(basename "$f" .actual.png)
  cp "$f" "tests/golden/$name.png"
  echo "promoted $name"
done
