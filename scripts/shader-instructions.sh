#!/usr/bin/env bash
# Instructions llvmpipe executes in the shaders of one `atmoglobe render`, counted by valgrind's
# callgrind: a deterministic measure of a shader change on a machine whose frame times vary by
# 10-20 % from run to run (docs/bench-volume.md, "Instruction counts").
#
#   scripts/shader-instructions.sh [--shaders DIR]... [-- RENDER_ARGS...]
#
# Each --shaders DIR (a copy of shaders/ with edits; "built-in" for the binary's own) is counted in
# its own callgrind run, two at a time. RENDER_ARGS default to the default scene at 320x180
# without map lines or legend. Prints per run: the instructions of all JIT-compiled code (llvmpipe's
# shaders: callgrind's anonymous object), of the largest such function (the marcher, in a volume
# scene), and the PNG's md5 (equal pictures, equal sums). Needs valgrind (apt-get install valgrind)
# and a built build/tools/atmoglobe. About 2 minutes a run; counts are exact, load does not matter.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bin=${ATMOGLOBE_BIN:-$root/build/tools/atmoglobe}
dirs=()
while [[ $# -gt 0 && $1 != -- ]]; do
  case $1 in
    --shaders) dirs+=("$2"); shift 2 ;;
    *) echo "usage: $0 [--shaders DIR]... [-- RENDER_ARGS...]" >&2; exit 2 ;;
  esac
done
[[ ${1:-} == -- ]] && shift
args=("$@")
[[ ${#args[@]} -gt 0 ]] || args=(--size 320x180 --no-map --no-legend)
[[ ${#dirs[@]} -gt 0 ]] || dirs=(built-in)
command -v valgrind > /dev/null || { echo "$0: valgrind is not installed (apt-get install valgrind)" >&2; exit 1; }
[[ -x $bin ]] || { echo "$0: $bin is not built (./scripts/build.sh)" >&2; exit 1; }
for d in "${dirs[@]}"; do
  [[ $d == built-in || -f $d/volume_march.frag ]] || { echo "$0: $d holds no volume_march.frag" >&2; exit 1; }
done
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

count() {  # count INDEX DIR
  local i=$1 d=$2
  local env=()
  [[ $d == built-in ]] || env=(ATMOGLOBE_SHADER_DIR="$(cd "$d" && pwd)")
  if ! env "${env[@]}" valgrind --tool=callgrind --smc-check=all-non-file --callgrind-out-file="$work/cg.$i" \
    "$bin" render "${args[@]}" -q -o "$work/$i.png" > "$work/$i.log" 2>&1; then
    echo "$d: the render failed (log below)"
    grep -av '^==' "$work/$i.log" | tail -5
    return
  fi
  callgrind_annotate --threshold=100 "$work/cg.$i" 2> /dev/null | grep '???:0x.*\[???\]' |
    awk -v d="$d" -v md5="$(md5sum < "$work/$i.png" | cut -c1-8)" \
      '{gsub(",", "", $1); v = $1 + 0; s += v; if (v > top) top = v}
       END {printf "%s: JIT instructions %d, largest function %d, picture md5 %s\n", d, s, top, md5}'
}

i=0
for d in "${dirs[@]}"; do
  count "$i" "$d" > "$work/out.$i" &
  i=$((i + 1))
  if (( i % 2 == 0 )); then wait; fi
done
wait
for ((j = 0; j < i; ++j)); do cat "$work/out.$j"; done
