#!/usr/bin/env bash
# Every bench a GPU can run, in one call of under 8 minutes on a lent GPU machine, from the bundle
# scripts/gpu-bundle.sh made (carried as .gpu/):
#
#   bash .gpu/gpu-bench.sh OUT_DIR
#
# 1. the grid bench on the SYNTHETIC regional and global grids (steps 250 and 1000 m, 1280x720 too);
# 2. with the bundle's compare-shaders (another revision's shaders, the same binary through
#    ATMOGLOBE_SHADER_DIR): the grid bench's default cells with those shaders and with ours,
#    alternately, 2 runs each, so that a change is measured side by side on one machine;
# 3. the radar bench (KLBB, AU40; DVR steps 250 and 1000 m and the step rule) at 320x180, all four
#    views, and at 1280x720, the two oblique views (their references at that size are in the
#    bundle; the down views' are not rendered yet);
# 4. several volumes (bench_volume_overlap);
# 5. networks of 1, 10, 40 and 160 SYNTHETIC radars and the rules on the Belgian pair
#    (bench_radar_network);
# 6. the scene-load bench (1/4/16 synthetic radars, 1/10 steps);
# 7. the SYNTHETIC global grid under texture limits, near and far (bench_grid_windows; its table is
#    appended to grid_bench.md: a lent machine returns at most 8 files);
# 8. samples per second against the fetch rate (bench_sample_rate, KLBB; appended to
#    volume_bench_1280.md).
# GPU_BENCH_STAGES="grids radar ..." runs only those stages (grids compare radar overlap networks
# scenes windows rate), e.g. to finish a run that a machine's time cut short.
# Every bench writes into one directory whose reference-cache/ starts as the bundle's, and runs
# from the bundle's run/ so that the radar files are ../shared/data/... as the cache keys say.
# Each stage is bounded by `timeout` so the rest still run; OUT_DIR gets the reports (at most 8
# files) and the log. The GPU is whatever the EGL device is (the line "GL:" in each report).
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
out=${1:?usage: gpu-bench.sh OUT_DIR}
mkdir -p "$out"
out=$(cd "$out" && pwd)
log=$out/gpu-bench.log
work=$(mktemp -d)
start=$(date +%s)
say() { echo "[$(($(date +%s) - start)) s] $*" | tee -a "$log"; }
# The GL dispatch packages, then our programs and their libraries.
# (GPU_BENCH_NO_DPKG=1 skips this, for a trial run on a machine that has them.)
if [[ -z ${GPU_BENCH_NO_DPKG:-} ]]; then
  for f in "$here"/*.deb; do dpkg -x "$f" /; done
  ldconfig
fi
export __EGL_VENDOR_LIBRARY_FILENAMES=${__EGL_VENDOR_LIBRARY_FILENAMES:-/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json}
[[ -f $__EGL_VENDOR_LIBRARY_FILENAMES ]] || unset __EGL_VENDOR_LIBRARY_FILENAMES
if command -v xz > /dev/null; then
  xz -dc "$here/bundle.tar.xz" | tar -x -C "$work"
else
  python3 -c 'import lzma, sys, tarfile; tarfile.open(fileobj=lzma.open(sys.argv[1])).extractall(sys.argv[2])' \
    "$here/bundle.tar.xz" "$work"
fi
export LD_LIBRARY_PATH=$work/lib
for f in proj/egm96_15.gtx xml/udunits; do
  [[ -e /usr/share/$f ]] || { mkdir -p "$(dirname "/usr/share/$f")" && cp -r "$work/share/$f" "/usr/share/$f"; }
done
ag=$work/bin/atmoglobe
bench=$work/bench
mkdir -p "$bench/reference-cache"
cp "$work"/reference-cache/*.ref "$bench/reference-cache/" 2>/dev/null
cd "$work/run" || exit 1
say "atmoglobe $(cat "$work/REVISION"), $(ls "$bench/reference-cache" | wc -l) cached references; $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null)"
"$ag" --version >> "$log" 2>&1 || { say "the binary does not start"; ldd "$ag" | grep "not found" | tee -a "$log"; exit 1; }
stages=" ${GPU_BENCH_STAGES:-grids compare radar overlap networks scenes windows rate} "
want() { [[ $stages == *" $1 "* ]]; }
stage() {  # stage NAME SECONDS COMMAND...
  local name=$1 limit=$2
  shift 2
  want "${name%% *}" || want "${name%%-*}" || return 0
  say "$name: $*"
  timeout "$limit" "$@" >> "$log" 2>&1
  local rc=$?
  say "$name: rc $rc"
}
stage grids 200 "$ag" bench --grids --no-peer --no-load --out "$bench" --steps 250 1000 --frames 7 -q
cp "$bench/grid_bench.md" "$out/" 2>/dev/null
if [[ -d $work/compare-shaders ]] && want compare; then
  old=$(cat "$work/compare-shaders/REVISION")
  {
    echo "# Grid bench, shaders of $old against $(cat "$work/REVISION"), one binary, alternating"
    echo
    echo "| run | shaders | view | size | cell | frame (ms) | mean | max | PSNR (dB) |"
    echo "|---|---|---|---|---|---|---|---|---|"
  } > "$out/compare.md"
  for run in 1 2; do
    for which in old new; do
      if [[ $which == old ]]; then export ATMOGLOBE_SHADER_DIR=$work/compare-shaders; else unset ATMOGLOBE_SHADER_DIR; fi
      stage "compare $which $run" 45 "$ag" bench --grids --no-peer --no-load --out "$bench" --steps 250 \
        --view global-space --view global-cyclone --view regional-oblique --frames 7 -q
      grep -E "\| (320x180|1280x720) \| dvr step 250 m, scale 1, linear( \(default\))? \|" "$bench/grid_bench.md" |
        sed "s/^|/| $run | $which ($([[ $which == old ]] && echo "$old" || cat "$work/REVISION")) |/" >> "$out/compare.md"
    done
  done
  unset ATMOGLOBE_SHADER_DIR
fi
stage radar 80 "$ag" bench --no-peer --no-big --out "$bench" --steps 250 1000 --frames 7 -q
cp "$bench/volume_bench.md" "$out/volume_bench_320.md" 2>/dev/null
stage radar-1280 80 "$ag" bench --no-peer --no-big --size 1280x720 --view KLBB-oblique --view AU40-oblique \
  --out "$bench" --steps 250 1000 --frames 7 -q
cp "$bench/volume_bench.md" "$out/volume_bench_1280.md" 2>/dev/null
if want overlap; then
  say "overlap"
  timeout 60 "$work/bin/bench_volume_overlap" --runs 3 > "$out/overlap.md" 2>> "$log"
  say "overlap: rc $?"
fi
if want networks; then
  say "networks"
  timeout 200 "$work/bin/bench_radar_network" --counts 1,10,40,160 --sizes 320x180,1280x720 --runs 3 --frames 5 \
    --separate-max 10 --far-field 1 --out "$bench/network" --data ../shared/data > "$out/network.md" 2>> "$log"
  say "networks: rc $?"
fi
stage scenes 150 "$ag" bench --scenes --load-runs 1 --out "$bench" -q
cp "$bench/scenes/scene-load.md" "$out/" 2>/dev/null
if want windows; then
  say "windows"
  timeout 90 "$work/bin/bench_grid_windows" --runs 3 --frames 3 --out "$bench" > "$bench/grid_windows.md" 2>> "$log"
  say "windows: rc $?"
  { echo; echo "# Near and far (bench_grid_windows)"; echo; cat "$bench/grid_windows.md"; } >> "$out/grid_bench.md"
fi
if want rate; then
  say "rate"
  timeout 60 "$work/bin/bench_sample_rate" --radar ../shared/data/radar_nexrad/KLBB20160601_150025_V06 --runs 3 \
    --frames 7 > "$bench/sample_rate.md" 2>> "$log"
  say "rate: rc $?"
  { echo; cat "$bench/sample_rate.md"; } >> "$out/volume_bench_1280.md"
fi
say "done"
