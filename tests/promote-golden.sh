#!/usr/bin/env bash
# Copies the images the golden-image test last rendered over the reviewed ones.
# Look at them first (build/test-output/*.actual.png and *.diff.png).
set -euo pipefail
cd "$(dirname "$0")/.."
for f in build/test-output/*.actual.png; do
  name=$(basename "$f" .actual.png)
  cp "$f" "tests/golden/$name.png"
  echo "promoted $name"
done
