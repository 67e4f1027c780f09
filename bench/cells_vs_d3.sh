#!/usr/bin/env bash
# Benchmark of issue 3: `geovor cells` on the 171,075 GeoNames cities to GeoJSON and to
# GeoPackage, whole process (wall time and peak memory from /usr/bin/time), beside
# d3-geo-voronoi's polygons() (npm) on the same points, then the validity of each output with
# GDAL/GEOS: invalid polygons, and the planar lon/lat area sum, which is 64800 square degrees
# for a correct RFC 7946 tiling.
# Each command runs RUNS times (default 3) after the input was read once (so that no run pays
# for a page cache the system has since evicted); the median wall time is compared, and the
# fastest and slowest runs are shown. /usr/bin/time gives wall times to 10 ms (3% of geovor's).
# Usage: [GEOVOR=binary] [RUNS=n] bench/cells_vs_d3.sh [CSV]   (default: the cities; work files in build/bench-d3/)
set -euo pipefail
runs=${RUNS:-3}
[[ $runs =~ ^[0-9]*[13579]$ ]] || { echo "RUNS must be an odd positive number (the median of the runs is compared)"; exit 2; }
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
work=$root/build/bench-d3
mkdir -p "$work"
input=${1:-}
if [[ -z $input ]]; then
  input=$work/cities.csv
  [[ -f $input ]] || gzip -dc "$root/datasets/geonames_cities.csv.gz" >"$input"
fi
# GEOVOR=path/to/geovor uses that binary instead of building build/tools/geovor.
if [[ -z ${GEOVOR:-} ]]; then
  "$root/scripts/build.sh" release geovor_cli >"$work/build.log" 2>&1 || { cat "$work/build.log"; exit 1; }
fi
geovor=${GEOVOR:-$root/build/tools/geovor}
if [[ ! -d $work/node/node_modules/d3-geo-voronoi ]]; then
  mkdir -p "$work/node"
  cp "$root/bench/d3/package.json" "$root/bench/d3/polygons.mjs" "$work/node/"
  (cd "$work/node" && npm install --no-audit --no-fund --silent >/dev/null)
fi
cp "$root/bench/d3/polygons.mjs" "$work/node/"

cat "$input" >/dev/null
# run NAME COMMAND...: RUNS times; the median, fastest and slowest wall seconds, and the largest
# peak RSS (MB), of the whole process.
declare -A wall fastest slowest rss
# With REMOVE=FILE, FILE is removed before each run, outside the time.
run() {
  local name=$1 walls=() peak=0 i w m
  shift
  for ((i = 0; i < runs; ++i)); do
    [[ -n ${REMOVE:-} ]] && rm -f "$REMOVE"
    /usr/bin/time -f "%e %M" -o "$work/$name.time" "$@" 2>"$work/$name.err" >/dev/null ||
      { echo "$name failed:"; cat "$work/$name.err"; return 1; }
    read -r w m <"$work/$name.time"
    walls+=("$w")
    ((m > peak)) && peak=$m
  done
  mapfile -t walls < <(printf '%s\n' "${walls[@]}" | sort -g)
  wall[$name]=${walls[$((runs / 2))]}
  fastest[$name]=${walls[0]}
  slowest[$name]=${walls[$((runs - 1))]}
  rss[$name]=$((peak / 1024))
}
run geovor_geojson "$geovor" cells "$input" -o "$work/geovor.geojson" --overwrite -q
# A new GeoPackage each time: --overwrite of an existing one replaces its layer in place, as
# ogr2ogr -overwrite does (a journaled update: 4.6 times the writes), which is another job.
REMOVE=$work/geovor.gpkg run geovor_gpkg "$geovor" cells "$input" -o "$work/geovor.gpkg" -q
run d3 node --max-old-space-size=16000 "$work/node/polygons.mjs" "$input" "$work/d3.geojson"

# check FILE LAYER GEOMETRY_COLUMN: invalid polygons, and the planar area sum in square degrees.
check() {
  local invalid area
  invalid=$(ogrinfo -ro -q -dialect SQLite -sql "SELECT COUNT(*) AS n FROM \"$2\" WHERE NOT ST_IsValid($3)" "$1" |
    sed -n 's/.*n (Integer) = //p')
  area=$(ogrinfo -ro -q -dialect SQLite -sql "SELECT SUM(ST_Area($3)) AS a FROM \"$2\"" "$1" |
    sed -n 's/.*a (Real) = //p')
  echo "$invalid $area"
}
read -r g_invalid g_area < <(check "$work/geovor.geojson" cells GEOMETRY)
read -r p_invalid p_area < <(check "$work/geovor.gpkg" cells geom)
d3_layer=$(ogrinfo -ro -q "$work/d3.geojson" | sed -n 's/^1: \([^ ]*\).*/\1/p')
read -r d_invalid d_area < <(check "$work/d3.geojson" "$d3_layer" GEOMETRY)
n=$(($(wc -l <"$input") - 1))

echo "cells of $n points ($(basename "$input")), whole process, median of $runs runs, on $(nproc) cores ($(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | xargs))"
printf '%-22s %9s %13s %9s %9s %14s\n' run wall_s fastest-slowest peak_MB invalid planar_deg2
line() { printf '%-22s %9s %13s %9s %9s %14s\n' "$1" "${wall[$2]}" "${fastest[$2]}-${slowest[$2]}" "${rss[$2]}" "$3" "$4"; }
line "geovor -> GeoJSON" geovor_geojson "$g_invalid" "$g_area"
line "geovor -> GeoPackage" geovor_gpkg "$p_invalid" "$p_area"
line "d3-geo-voronoi" d3 "$d_invalid" "$d_area"
ratio() { echo "$1 / $2" | bc -l | xargs printf '%.1f'; }
echo "speedup (d3 / geovor GeoJSON): $(ratio "${wall[d3]}" "${wall[geovor_geojson]}")x on the medians;" \
  "$(ratio "${fastest[d3]}" "${slowest[geovor_geojson]}")x for d3's fastest run against geovor's slowest"
echo "a correct tiling of the sphere in lon/lat has a planar area sum of 64800 square degrees"
