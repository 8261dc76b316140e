#!/usr/bin/env bash
# fuzz/run.sh BUILD_DIR SECONDS [TARGET...]   run each fuzz target (default: all) for SECONDS.
# Corpora: the committed seeds and kept crashers of fuzz/corpus/NAME, plus small real files from
# the sample data ($ATMOGLOBE_TEST_DATA, else ../shared/data; copied at run time, never committed),
# gathered in BUILD_DIR/fuzz-work/corpus/NAME (libFuzzer adds what it finds there). A crash, leak,
# timeout or out-of-memory input is written to BUILD_DIR/fuzz-work/findings/NAME/ and makes the
# script exit non-zero after all targets ran. $ATMOGLOBE_FUZZ_FLAGS: more libFuzzer flags (long runs:
# "-fork=1 -ignore_crashes=1 -ignore_ooms=1 -ignore_timeouts=1" go on past findings, to triage after). Each target's last libFuzzer status line (#runs,
# cov, ft, corp, exec/s) is appended to BUILD_DIR/fuzz-work/summary.txt.
set -uo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
build="$(cd "$1" && pwd)"; seconds="$2"; shift 2
data="${ATMOGLOBE_TEST_DATA:-$(cd "$here/../.." && pwd)/shared/data}"
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  targets=(cfradial odim nexrad sigmet rainbow compression grid grib scene pal stations image pyramid overlay)
fi
work="$build/fuzz-work"
export LSAN_OPTIONS="suppressions=$here/../scripts/lsan-suppressions.txt${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"
mkdir -p "$work"
failed=()

# Real seeds: small files whole, the head of large ones whose readers must cope with truncation.
seed() {  # seed NAME FILE [HEAD_BYTES]
  local dir="$work/corpus/$1" f="$2" n="${3:-}"
  [ -f "$f" ] || return 0
  if [ -n "$n" ]; then head -c "$n" "$f" > "$dir/real-head-$(basename "$f")"; else cp "$f" "$dir/real-$(basename "$f")"; fi
}

for t in "${targets[@]}"; do
  exe="$build/fuzz/fuzz_$t"
  [ -x "$exe" ] || { echo "fuzz/run.sh: $exe not built (cmake -DATMOGLOBE_FUZZ=ON)" >&2; exit 2; }
  mkdir -p "$work/corpus/$t" "$work/findings/$t"
  cp -f "$here/corpus/$t"/* "$work/corpus/$t/" 2>/dev/null || true
  # GRIB: ecCodes' own sample messages (Debian libeccodes-data), small and of many grid types.
  if [ "$t" = grib ]; then
    for f in /usr/share/eccodes/samples/{GRIB1,GRIB2,gg_sfc_grib2,lambert_bf_grib2,polar_stereographic_pl_grib2,regular_ll_pl_grib1,rotated_ll_pl_grib2,reduced_gg_pl_32_grib2}.tmpl; do
      [ -f "$f" ] && cp -f "$f" "$work/corpus/grib/sample-$(basename "$f")"
    done
  fi
  if [ -d "$data" ]; then
    case "$t" in
      cfradial) for f in "$data"/radar_cfradial/*.nc; do [ "$(stat -c %s "$f")" -le 2000000 ] && seed cfradial "$f"; done ;;
      odim) for f in "$data"/radar_odim/lfpw_scans/*65541.h5 "$data"/radar_odim/lfpw_scans/*065125.h5; do seed odim "$f"; done ;;
      nexrad) for f in "$data"/radar_nexrad/*; do seed nexrad "$f" 300000; done ;;
      sigmet) for f in "$data"/radar_sigmet/*; do seed sigmet "$f" 200000; done ;;
      rainbow) for f in "$data"/radar_rainbow/*.vol; do seed rainbow "$f"; done ;;
      stations) for f in "$data"/stations/*.json; do seed stations "$f"; done ;;
      grib) for f in "$data"/grids_grib/*; do [ "$(stat -c %s "$f")" -le 60000 ] && seed grib "$f"; done ;;
      overlay) for f in "$data"/overlays/*.geojson "$data"/overlays/*.kml; do [ -f "$f" ] && [ "$(stat -c %s "$f")" -le 200000 ] && seed overlay "$f"; done ;;
    esac
  fi
  # Inputs up to the largest seed (libFuzzer's default truncates at 1 MiB, which breaks netCDF seeds).
  maxlen="$(find "$work/corpus/$t" -type f -printf '%s\n' | sort -n | tail -1)"
  [ "${maxlen:-0}" -ge 4096 ] || maxlen=4096
  log="$work/$t.log"
  echo "== fuzz_$t: ${seconds}s over $(ls "$work/corpus/$t" | wc -l) inputs"
  # -timeout: an input taking 20 s is a hang; -rss_limit_mb: memory bounded well below the machine.
  # Short runs (under 60 s: CI) only replay the corpus of the targets that reach HDF5 (netCDF-4
  # inputs): mutated HDF5 files crash libhdf5 1.10.8 itself within seconds (docs/robustness.md),
  # which no caller can prevent and which would fail CI at random. Long runs fuzz them too.
  budget=(-max_total_time="$seconds")
  case "$t" in cfradial | odim | grid) [ "$seconds" -lt 60 ] && budget=(-runs=0) ;; esac
  "$exe" "$work/corpus/$t" "${budget[@]}" -timeout=20 -rss_limit_mb=2560 -print_final_stats=1 -max_len="$maxlen" ${ATMOGLOBE_FUZZ_FLAGS:-} \
    -artifact_prefix="$work/findings/$t/" > "$log" 2>&1
  rc=$?
  last="$(grep -E '^#[0-9]+' "$log" | tail -1)"
  runs="$(grep -E '^stat::number_of_executed_units' "$log" | awk '{print $2}')"
  echo "fuzz_$t seconds=$seconds runs=${runs:-?} rc=$rc last: $last" | tee -a "$work/summary.txt"
  if [ $rc -ne 0 ]; then
    grep -E 'ERROR|SUMMARY|fuzz: |Test unit written|assertion' "$log" | grep -v '^ECCODES' | head -8
    # A timeout is confirmed by running its input again alone: a hang repeats; a unit that ran
    # 27 s once on CI's shared machine (an 858-byte GeoJSON, fuzz_overlay) and took milliseconds
    # again, and in a million executions locally under -timeout=4, is the machine stalling, not
    # the code. The input stays in findings/ either way.
    # Only a log whose findings are all timeouts (no crash, leak, sanitizer report or
    # out-of-memory input), each timeout's unit finishing when run again.
    repeated=1
    if grep -q 'libFuzzer: timeout' "$log" &&
      ! grep -qE 'deadly signal|AddressSanitizer|LeakSanitizer|UndefinedBehaviorSanitizer|runtime error|out-of-memory|crash-[0-9a-f]|leak-[0-9a-f]|oom-[0-9a-f]' "$log"; then
      repeated=0
      for unit in $(sed -n 's/.*Test unit written to \(.*timeout-[0-9a-f]*\).*/\1/p' "$log" | sort -u); do
        if [ -f "$unit" ] && "$exe" "$unit" -timeout=20 -rss_limit_mb=2560 > "$log.rerun" 2>&1; then
          echo "fuzz_$t: the timeout did not repeat: $unit ran again in $(sed -n 's/.*Executed .* in \([0-9]*\) ms.*/\1/p' "$log.rerun" | tail -1) ms (kept in findings, not a failure)"
        else
          repeated=1
        fi
      done
    fi
    [ "$repeated" -eq 0 ] || failed+=("$t")
  fi
done
if [ ${#failed[@]} -ne 0 ]; then
  echo "fuzz/run.sh: findings in: ${failed[*]} (logs and inputs in $work)" >&2
  exit 1
fi
