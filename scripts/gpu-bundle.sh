#!/usr/bin/env bash
# Packs what scripts/gpu-bench.sh needs on a machine that has a GPU but neither our Debian
# packages nor ../shared: the built programs and the shared libraries they load (not libc or the
# GL/EGL dispatch, which come from that machine's driver and the glvnd packages fetched here), the
# bench's radar files, and a copy of the shaders of another revision to compare against.
#
#   scripts/gpu-bundle.sh [--build DIR] [--data DIR] [--compare-rev REV] [--references DIR]... [--out DIR]
#
# --references DIR (repeatable) adds the bench reference images cached in DIR (a bench --out's
# reference-cache/): the radar references take minutes each even on 16 threads, so a GPU run is
# timed against references rendered here beforehand. Their doubles are cut to float precision
# (the low 29 mantissa bits zeroed: a relative change under 6e-8, against the 1/255 steps the
# bench counts errors in), which halves their packed size (a 1280x720 one to under 2 MB).
#
# A call to the GPU machine carries at most 64 MiB with the repository, so the bundle is packed
# with xz -9e and ICU's 31 MB data library is replaced by a stub of the same name and symbol:
# the benches never call ICU (only libxml2's and GDAL's text recoding would), and ICU answers a
# call with an error, not a crash, when its data's header is wrong.
#
# Writes DIR (default .gpu/, ignored by git) holding bundle.tar.xz, the glvnd .deb files and
# gpu-bench.sh: carry it to the GPU machine and run `bash .gpu/gpu-bench.sh OUT` there.
set -euo pipefail
cd "$(dirname "$0")/.."
build=build data=../shared/data rev="" out=.gpu
refs=()
while [[ $# -gt 0 ]]; do
  case "$1" in
    --build) build=$2; shift 2 ;;
    --data) data=$2; shift 2 ;;
    --compare-rev) rev=$2; shift 2 ;;
    --references) refs+=("$2"); shift 2 ;;
    --out) out=$2; shift 2 ;;
    *) echo "gpu-bundle.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
programs=("$build/tools/atmoglobe" "$build/tools/bench/bench_volume_overlap" "$build/tools/bench/bench_radar_network"
  "$build/tools/bench/bench_grid_windows" "$build/tools/bench/bench_sample_rate")
for p in "${programs[@]}"; do
  [[ -x $p ]] || { echo "gpu-bundle.sh: $p: not built (./scripts/build.sh)" >&2; exit 1; }
done
files=(radar_nexrad/KLBB20160601_150025_V06 radar_odim/40_20181220_060630.pvol.h5 radar_odim/bewid.pvol.hdf
  radar_odim/behel_loop/20200207130000.rad.behel.pvol.dbzh.scanz.hdf)
for f in "${files[@]}"; do
  [[ -f $data/$f ]] || { echo "gpu-bundle.sh: $data/$f: missing (the radar bench's files)" >&2; exit 1; }
done
stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT
# The radar files under shared/data, beside a working directory run/: the bench is run from run/
# with its default --data ../shared/data, the path the cached references are keyed by.
mkdir -p "$stage/bin" "$stage/lib" "$stage/shared/data/radar_nexrad" "$stage/shared/data/radar_odim/behel_loop" \
  "$stage/run" "$stage/reference-cache"
cp "${programs[@]}" "$stage/bin/"
for f in "${files[@]}"; do cp "$data/$f" "$stage/shared/data/$f"; done
for d in "${refs[@]}"; do
  [[ -d $d ]] || { echo "gpu-bundle.sh: $d: no such directory (a bench reference cache)" >&2; exit 1; }
  find "$d" -maxdepth 1 -name '*.ref' -exec cp -n {} "$stage/reference-cache/" \;
done
# File layout (tools/bench/include/atmoglobe/bench/ReferenceCache.h): uint32 key length, key,
# two int32, then the doubles; a file that does not parse is left as it is.
python3 - "$stage/reference-cache" <<'PY'
import array, pathlib, struct, sys
mask = ~((1 << 29) - 1) & 0xFFFFFFFFFFFFFFFF
for f in pathlib.Path(sys.argv[1]).glob("*.ref"):
    b = f.read_bytes()
    if len(b) < 4: continue
    off = 4 + struct.unpack_from("<I", b, 0)[0] + 8
    if off > len(b) or (len(b) - off) % 8: continue
    a = array.array("Q"); a.frombytes(b[off:])
    f.write_bytes(b[:off] + array.array("Q", (x & mask for x in a)).tobytes())
PY
# Every library the programs load, but the C library, the loader and the GL dispatch (the GPU
# machine's own, with its driver).
skip='^(linux-vdso|ld-linux|libc\.|libm\.|libpthread|libdl\.|librt\.|libEGL|libGL|libOpenGL|libGLX|libGLdispatch|libgbm|libdrm)'
for p in "${programs[@]}"; do ldd "$p"; done | awk '$3 ~ /^\// {print $3}' | sort -u | while read -r lib; do
  name=$(basename "$lib")
  [[ $name =~ $skip ]] || cp -L "$lib" "$stage/lib/$name"
done
for icu in "$stage"/lib/libicudata.so.*; do
  [[ -f $icu ]] || continue
  sym=$(nm -D --defined-only "$icu" | awk '$3 ~ /^icudt[0-9]+_dat$/ {print $3}')
  [[ -n $sym ]] || { echo "gpu-bundle.sh: $icu: no icudt*_dat symbol" >&2; exit 1; }
  echo "const char $sym[64] __attribute__((aligned(16))) = {0};" |
    cc -x c -shared -fPIC -o "$icu" -Wl,-soname,"$(basename "$icu")" -
done
# Data files the readers open by their Debian paths: the EGM96 geoid (proj-data) and the UDUNITS-2
# database (libudunits2-data); gpu-bench.sh puts them there when that machine lacks them.
mkdir -p "$stage/share/proj" "$stage/share/xml"
cp /usr/share/proj/egm96_15.gtx "$stage/share/proj/"
cp -r /usr/share/xml/udunits "$stage/share/xml/"
if [[ -n $rev ]]; then
  mkdir -p "$stage/compare-shaders"
  git archive "$rev" shaders | tar -x -C "$stage/compare-shaders" --strip-components=1
  git rev-parse --short "$rev" > "$stage/compare-shaders/REVISION"
fi
git rev-parse --short HEAD > "$stage/REVISION"
mkdir -p "$out"
tar -C "$stage" -cf - . | xz -T0 -9e > "$out/bundle.tar.xz"
cp scripts/gpu-bench.sh "$out/"
# The GL dispatch libraries (glvnd) the driver's EGL needs, as .deb files (unpacked there).
if ! ls "$out"/*.deb > /dev/null 2>&1; then
  (cd "$out" && apt-get download libegl1 libglvnd0 libopengl0 libgl1 libglx0 libgles2 > /dev/null)
fi
du -sh "$out"
