#!/usr/bin/env bash
# Installs the Debian 12 packages atmoglobe builds, runs and tests with.
# Fast when everything is present: one dpkg-query, no apt call.
set -euo pipefail

PKGS=(
  cmake g++ make pkg-config
  libgeographiclib-dev libglfw3-dev libglm-dev libtinygltf-dev nlohmann-json3-dev
  libnetcdf-dev libhdf5-dev libstb-dev libpng-dev libgtest-dev libepoxy-dev libegl-dev libgl-dev
  libegl-mesa0 libgl1-mesa-dri libbz2-dev libzip-dev
  libcli11-dev
  libeccodes-dev libeccodes-tools   # GRIB grids (volume/src/grid/Grib*); grib_get_data in the tests
  libproj-dev   # GRIB's projected grids (volume/src/grid/GribProjection.cpp)
  libudunits2-dev   # units of grid coordinates (volume/src/grid/VerticalCoordinate.cpp)
  proj-data proj-bin xplanet-images xvfb xauth
  opencollada-tools libxml2-utils nodejs unzip
  netcdf-bin clang-format zlib1g-dev libexpat1-dev teem-apps
  fonts-dejavu-core libimgui-dev
  tzdata   # /usr/share/zoneinfo/zone1970.tab: the viewer's fly-to place names (engine/Gazetteer.h)
  gmt-gshhg libgdal-dev
  libgif-dev   # animated GIF of render --time-series (engine/AnimationWriter)
  ffmpeg   # its MP4 (engine/AnimationWriter runs ffmpeg); ffprobe checks the MP4 in the tests
  ccache   # the sanitized and fuzz builds of scripts/test-sanitized.sh (CI)
  clang libclang-rt-14-dev   # libFuzzer for the fuzz targets (fuzz/, scripts/test-sanitized.sh)
  python3 python3-dev pybind11-dev python3-numpy python3-pytest   # the Python module (python/)
  python3-distributed python3-xarray   # its archives on Dask (python/atmoglobe/archive.py), to_xarray
  slurm-wlm munge   # a one-node Slurm cluster for the job-array test (tests/tools/SlurmShards.sh)
)

missing=()
for p in "${PKGS[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "atmoglobe: installing missing Debian packages: ${missing[*]}" >&2
SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then SUDO="sudo"; else
    echo "atmoglobe: need root (or sudo) to install: ${missing[*]}" >&2; exit 1
  fi
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
$SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
