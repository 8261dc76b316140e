#!/usr/bin/env bash
# Packs what scripts/gpu-bench.sh needs on a machine that has a GPU but neither our Debian
# packages nor ../shared: the built programs and the shared libraries they load (not libc or the
# GL/EGL dispatch, which come from that machine's driver and the glvnd packages fetched here), the
# bench's radar files, and a copy of the shaders of another revision to compare against.
#
#   scripts/gpu-bundle.sh [--build DIR] [--data DIR] [--compare-rev REV] [--out DIR]
#
# Writes DIR (default .gpu/, ignored by git) holding bundle.tar.xz, the glvnd .deb files and
# gpu-bench.sh: carry it to the GPU machine and run `bash .gpu/gpu-bench.sh OUT` there.
set -euo pipefail
cd "$(dirname "$0")/.."
build=build data=../shared/data rev="" out=.gpu
while [[ $# -gt 0 ]]; do
  case "$1" in
    --build) build=$2; shift 2 ;;
    --data) data=$2; shift 2 ;;
    --compare-rev) rev=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    *) echo "gpu-bundle.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
programs=("$build/tools/atmoglobe" "$build/tools/bench/bench_volume_overlap")
for p in "${programs[@]}"; do
  [[ -x $p ]] || { echo "gpu-bundle.sh: $p: not built (./scripts/build.sh)" >&2; exit 1; }
done
files=(radar_nexrad/KLBB20160601_150025_V06 radar_odim/40_20181220_060630.pvol.h5)
for f in "${files[@]}"; do
  [[ -f $data/$f ]] || { echo "gpu-bundle.sh: $data/$f: missing (the radar bench's files)" >&2; exit 1; }
done
stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT
mkdir -p "$stage/bin" "$stage/lib" "$stage/data/radar_nexrad" "$stage/data/radar_odim"
cp "${programs[@]}" "$stage/bin/"
for f in "${files[@]}"; do cp "$data/$f" "$stage/data/$f"; done
# Every library the programs load, but the C library, the loader and the GL dispatch (the GPU
# machine's own, with its driver).
skip='^(linux-vdso|ld-linux|libc\.|libm\.|libpthread|libdl\.|librt\.|libEGL|libGL|libOpenGL|libGLX|libGLdispatch|libgbm|libdrm)'
for p in "${programs[@]}"; do ldd "$p"; done | awk '$3 ~ /^\// {print $3}' | sort -u | while read -r lib; do
  name=$(basename "$lib")
  [[ $name =~ $skip ]] || cp -L "$lib" "$stage/lib/$name"
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
tar -C "$stage" -cf - . | xz -T0 -6 > "$out/bundle.tar.xz"
cp scripts/gpu-bench.sh "$out/"
# The GL dispatch libraries (glvnd) the driver's EGL needs, as .deb files (unpacked there).
if ! ls "$out"/*.deb > /dev/null 2>&1; then
  (cd "$out" && apt-get download libegl1 libglvnd0 libopengl0 libgl1 libglx0 libgles2 > /dev/null)
fi
du -sh "$out"
