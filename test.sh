#!/usr/bin/env bash
# ./test.sh   install what is missing, build (Release) and run every test through ctest.
# Real sample data (not in the repository): $ATMOGLOBE_TEST_DATA, else ../shared/data beside the
# checkout. Without them the tests that read them (ctest label realdata) are skipped, with the
# reason. With CI=true they must all run: a missing data directory, or any realdata test that
# does not run, is a failure (ATMOGLOBE_REQUIRE_TEST_DATA=1 turns each skip into a failure).
# With CI=true (or ATMOGLOBE_SANITIZED_TESTS=1) the whole suite then runs again under
# AddressSanitizer + UndefinedBehaviorSanitizer, the threads tests (ctest label) under
# ThreadSanitizer, followed by a short fuzz run of every fuzz target (scripts/test-sanitized.sh, in
# build-sanitize/, build-tsan/ and build-fuzz/); ATMOGLOBE_SANITIZED_TESTS=0 leaves it out. Its time
# on CI's 2-core machine: docs/robustness.md, "Sanitizers in CI".
set -euo pipefail
cd "$(dirname "$0")"
start=$SECONDS
data="${ATMOGLOBE_TEST_DATA:-$(cd .. && pwd)/shared/data}"
if [ "${CI:-}" = "true" ]; then
  if [ ! -d "$data" ]; then
    echo "test.sh: CI=true, but the real sample data are not at $data;" \
         "CI runs every realdata test: set ATMOGLOBE_TEST_DATA to the data directory" >&2
    exit 1
  fi
  export ATMOGLOBE_REQUIRE_TEST_DATA=1
fi
./scripts/install-deps.sh
./scripts/install-validators.sh   # glTF validator (npm) used by the export tests
./scripts/build.sh all
cd build
realdata="$(ctest -N -L realdata | sed -n 's/^ *Test *#[0-9]*: //p' | sort)"
log="$(mktemp)"
trap 'rm -f "$log"' EXIT
ctest --output-on-failure --timeout 900 -j "$(nproc)" 2>&1 | tee "$log"

# Skipped realdata tests: ctest lists skipped tests as "  N - NAME (Skipped)".
skipped="$(sed -n 's/^[[:space:]]*[0-9]* - \(.*\) (Skipped)$/\1/p' "$log" | sort)"
skipped_realdata="$(comm -12 <(echo "$realdata") <(echo "$skipped") | sed '/^$/d')"
if [ -n "$skipped_realdata" ]; then
  n="$(echo "$skipped_realdata" | wc -l)"
  if [ "${CI:-}" = "true" ]; then
    echo "test.sh: CI=true, but $n realdata tests were skipped (data at $data):" >&2
    echo "$skipped_realdata" | sed 's/^/  /' >&2
    exit 1
  fi
  echo "test.sh: $n of $(echo "$realdata" | wc -l) realdata tests skipped (set ATMOGLOBE_TEST_DATA), because:"
  grep -o 'real sample data not found at [^;]*(set ATMOGLOBE_TEST_DATA)' Testing/Temporary/LastTest.log |
    sort | uniq -c | sed 's/^ */  /' || true
fi
cd ..
echo "test.sh: Release build and tests done after $((SECONDS - start)) s"
sanitized="${ATMOGLOBE_SANITIZED_TESTS:-}"
if [ -z "$sanitized" ] && [ "${CI:-}" = "true" ]; then sanitized=1; fi
if [ "$sanitized" = "1" ]; then
  ./scripts/test-sanitized.sh
  echo "test.sh: all done after $((SECONDS - start)) s"
fi
