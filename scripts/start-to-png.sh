#!/usr/bin/env bash
# Process start to the PNG written, `atmoglobe render -q -o ...` of the default scene (or RENDER_ARGS),
# for one or more builds run in turn (A, B, A, B, ...) so that a busy machine slows them alike:
# the side-by-side comparison of docs/bench-globe.md, "Process start to the first PNG".
#
#   scripts/start-to-png.sh [--runs N] BIN... [-- RENDER_ARGS...]
#
# BIN: an atmoglobe binary (copy the old build's build/tools/atmoglobe aside first). Prints each
# binary's times sorted, its median and its ratio to the first binary's median, and whether the
# PNGs are the same bytes. Wall clock of the whole command, measured here with `date +%s.%N`.
set -euo pipefail
runs=7
bins=()
while [[ $# -gt 0 && $1 != -- ]]; do
  case $1 in
    --runs) runs=$2; shift 2 ;;
    -*) echo "usage: $0 [--runs N] BIN... [-- RENDER_ARGS...]" >&2; exit 2 ;;
    *) bins+=("$1"); shift ;;
  esac
done
[[ ${1:-} == -- ]] && shift
[[ ${#bins[@]} -gt 0 ]] || { echo "usage: $0 [--runs N] BIN... [-- RENDER_ARGS...]" >&2; exit 2; }
[[ $runs =~ ^[1-9][0-9]*$ ]] || { echo "$0: --runs $runs: expected a whole number of runs, 1 or more" >&2; exit 2; }
for b in "${bins[@]}"; do [[ -x $b ]] || { echo "$0: $b: not an executable" >&2; exit 1; }; done
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for ((r = 0; r < runs; ++r)); do
  for i in "${!bins[@]}"; do
    start=$(date +%s.%N)
    if ! "${bins[$i]}" render -q "$@" -o "$out/$i.png" > /dev/null 2> "$out/$i.err"; then
      echo "$0: ${bins[$i]} failed:" >&2
      cat "$out/$i.err" >&2
      exit 1
    fi
    end=$(date +%s.%N)
    echo "$end - $start" | bc >> "$out/$i.times"
  done
done
first=
for i in "${!bins[@]}"; do
  sorted=$(sort -n "$out/$i.times" | tr '\n' ' ')
  median=$(sort -n "$out/$i.times" | awk '{a[NR] = $1} END {print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2}')
  [[ -n $first ]] || first=$median
  same=$(cmp -s "$out/0.png" "$out/$i.png" && echo "the same PNG as the first" || echo "a different PNG from the first")
  printf '%s: median %.3f s (%.2fx the first), %s\n  runs: %s\n' "${bins[$i]}" "$median" \
    "$(echo "$median / $first" | bc -l)" "$same" "$sorted"
done
