#!/usr/bin/env bash
# Installs the Debian 12 packages that geovor needs to build and test, only those missing.
# Silent when everything is installed. Needs root when something is missing.
set -euo pipefail

packages=(
  build-essential cmake ninja-build
  libcgal-dev libgmp-dev libmpfr-dev libgeographiclib-dev libgdal-dev gdal-bin libgeos-dev
  libgtest-dev libgmock-dev libcli11-dev libbenchmark-dev libnanoflann-dev
  clang-14 libclang-rt-14-dev llvm-14
  python3-shapely python3-pyproj python3-numpy python3-geographiclib
  pybind11-dev python3-dev python3-venv python3-pip python3-setuptools python3-wheel python3-pytest
  python3-scipy python3-pandas python3-geopandas python3-dask python3-distributed python3-sklearn
  python3-mpmath python3-rtree libeigen3-dev libboost-dev libjs-leaflet
  chromium chromium-driver python3-selenium python3-qgis qgis-providers
  qgis  # qgis_process.bin: the QGIS plugin's test (tests/qgis)
)

missing=()
for pkg in "${packages[@]}"; do
  # shellcheck disable=SC2016  # ${Status} is dpkg-query's format, not a shell expansion
  status=$(dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null || true)
  if [[ $status != *" installed" ]]; then
    missing+=("$pkg")
  fi
done

if ((${#missing[@]} == 0)); then
  exit 0
fi

if ((EUID != 0)); then
  echo "install-deps.sh: missing Debian packages: ${missing[*]}" >&2
  echo "install-deps.sh: run this script as root, or: sudo apt-get install ${missing[*]}" >&2
  exit 1
fi

echo "install-deps.sh: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
apt-get update
apt-get install -y --no-install-recommends "${missing[@]}"
