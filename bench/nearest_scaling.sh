#!/usr/bin/env bash
# Scaling of `geovor nearest` with threads, end to end (loading the index, parsing, locating,
# formatting, writing a file): 2^20 sites uniform on the sphere (an index file made by
# `geovor index`) and 2^22 coherent queries (a random walk, 0.1-degree steps), 1 and 2 threads,
# for this build and for a reference binary in the same run, interleaved; prints the best wall
# time of RUNS runs of each and the ratio 1 thread / 2 threads. On a shared machine the best of
# several runs is the figure least disturbed by other work. Also checks that every output is
# byte-identical to the reference's 1-thread output.
# Usage: [RUNS=n] [SITES=n] [QUERIES=n] [REF=old/geovor] bench/nearest_scaling.sh [NEW=build/tools/geovor]
set -euo pipefail
runs=${RUNS:-5}
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
new=${1:-$root/build/tools/geovor}
ref=${REF:-}
sites=${SITES:-1048576}
queries=${QUERIES:-4194304}
work=$root/build/bench-nearest
mkdir -p "$work"
sites_csv=$work/sites_$sites.csv
queries_csv=$work/walk_$queries.csv
index=$work/sites_$sites.gvi
if [[ ! -f $sites_csv ]]; then
  awk -v n="$sites" 'BEGIN { srand(1); print "id,lat,lon"; pi = atan2(0, -1)
    for (i = 0; i < n; i++) printf "s%d,%.6f,%.6f\n", i, asin(2 * rand() - 1) * 180 / pi, 360 * rand() - 180 }
    function asin(x) { return atan2(x, sqrt(1 - x * x)) }' >"$sites_csv"
fi
if [[ ! -f $queries_csv ]]; then
  awk -v n="$queries" 'BEGIN { srand(2); lat = 10; lon = 20; print "lat,lon"
    for (i = 0; i < n; i++) {
      lat += 0.2 * rand() - 0.1; lon += 0.2 * rand() - 0.1
      if (lat > 89) lat = 178 - lat; if (lat < -89) lat = -178 - lat
      if (lon >= 180) lon -= 360; if (lon < -180) lon += 360
      printf "%.6f,%.6f\n", lat, lon } }' >"$queries_csv"
fi
[[ -f $index ]] || "$new" index "$sites_csv" -o "$index" >/dev/null
cat "$index" "$queries_csv" >/dev/null  # in the page cache for every run

declare -A best
bins=(new)
[[ -n $ref ]] && bins+=(ref)
for ((r = 0; r < runs; r++)); do
  for b in "${bins[@]}"; do
    exe=$new
    [[ $b == ref ]] && exe=$ref
    for t in 1 2; do
      out=$work/out_${b}_$t.csv
      start=$(date +%s.%N)
      "$exe" nearest --sites "$index" --queries "$queries_csv" -o "$out" --overwrite --threads "$t"
      end=$(date +%s.%N)
      s=$(echo "$end - $start" | bc)
      key=${b}_$t
      if [[ -z ${best[$key]:-} ]] || (($(echo "$s < ${best[$key]}" | bc))); then best[$key]=$s; fi
    done
  done
done
base=$work/out_new_1.csv
[[ -n $ref ]] && base=$work/out_ref_1.csv
for b in "${bins[@]}"; do
  for t in 1 2; do
    cmp -s "$base" "$work/out_${b}_$t.csv" || echo "DIFFERENT OUTPUT: $b, $t threads"
  done
done
printf '%s sites, %s coherent queries, best of %s runs (wall seconds, end to end)\n' "$sites" "$queries" "$runs"
printf '%-8s %10s %10s %8s\n' binary "1 thread" "2 threads" ratio
for b in "${bins[@]}"; do
  printf '%-8s %10.3f %10.3f %8.2f\n' "$b" "${best[${b}_1]}" "${best[${b}_2]}" "$(echo "${best[${b}_1]} / ${best[${b}_2]}" | bc -l)"
done
