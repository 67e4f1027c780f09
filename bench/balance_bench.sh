#!/usr/bin/env bash
# The balance benchmark of issue 33 in one go: geovor_bench_balance on the bundled weather
# stations with equal shares and with the synthetic capacity 1 + (row mod 5) (they have no
# capacity column; see balance_bench.cpp), and on the 171,075 cities with equal shares, each
# against Lloyd's iterations; prints each run's summary line (the full logs stay in LOGS).
# Lloyd's iterations after 10, 50 and 200 (LLOYD_CITIES for the cities: 200 take 35 to 45 s there).
# Takes about 3 minutes on 2 cores. Exit: the last failing case's (1: not converged), else 0.
# Usage: [LOGS=dir] [LLOYD_CITIES=10,50,200] bench/balance_bench.sh [BUILD_DIR=build]
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${1:-$root/build}
bench=$build/bench/geovor_bench_balance
logs=${LOGS:-$build/bench-balance}
mkdir -p "$logs"
[[ -x $bench ]] || { echo "balance_bench.sh: no $bench; build it: scripts/build.sh release geovor_bench_balance" >&2; exit 2; }

status=0
# run NAME ARGS...: one case, its log in $logs/NAME.log, its summary on stdout.
run() {
  local name=$1
  shift
  "$bench" "$@" >"$logs/$name.log" 2>&1 || status=$?
  grep '^summary: ' "$logs/$name.log" || { echo "$name: no summary (exit $status), see $logs/$name.log"; tail -3 "$logs/$name.log"; }
}

run stations_equal "$root/datasets/weather_stations.csv"
run stations_capacity "$root/datasets/weather_stations.csv" --synthetic-capacity
run cities_equal "$root/datasets/geonames_cities.csv.gz" --gz --lloyd "${LLOYD_CITIES:-10,50,200}"
exit "$status"
