#!/usr/bin/env bash
# Usage: [ONLY=REGEX] tests/cli/compare_with_reference.sh REF_GEOVOR NEW_GEOVOR [WORKDIR]
# Runs the same `geovor cells`, `delaunay` and `relax` jobs with two builds of geovor (each with
# its geovor-gdal beside it) and checks that they write the same bytes: every output file (a
# GeoPackage as ogrinfo's dump of it, since the file holds a timestamp), stdout, stderr and the
# exit code. For refactorings that must not change any output. Prints one line per job and a
# summary; exits 1 on any difference. ONLY runs the jobs whose name matches REGEX.
set -uo pipefail
ref=$(realpath "$1")
new=$(realpath "$2")
work=${3:-$(mktemp -d /tmp/geovor_compare_XXXXXX)}
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
mkdir -p "$work"
cities=$work/geonames_cities.csv
[[ -f $cities ]] || gunzip -c "$root/datasets/geonames_cities.csv.gz" >"$cities"
stations=$root/datasets/weather_stations.csv
fixtures=$root/tests/cli/fixtures
jobs=0
failed=0

# run_case NAME ARGS...: runs `geovor ARGS...` in $work/{ref,new}/NAME (outputs relative to it).
run_case() {
  local name=$1
  shift
  [[ $name =~ ${ONLY:-.} ]] || return 0
  local side bin dir
  for side in ref new; do
    [[ $side == ref ]] && bin=$ref || bin=$new
    dir=$work/$side/$name
    rm -rf "$dir"
    mkdir -p "$dir"
    (cd "$dir" && "$bin" "$@" >stdout.out 2>stderr.out; echo $? >rc.out)
    # What may differ: relax's time per iteration, and the binary's path (in --help's usage).
    sed -E -i -e '/^ +[0-9]+ +[-+.e0-9]+ +[.0-9]+ +[.0-9]+ +[0-9]+ +[.0-9]+$/s/[.0-9]+$/SECONDS/' \
      -e "s|$bin|geovor|g" "$dir/stderr.out" "$dir/stdout.out"
    for f in "$dir"/*.gpkg; do
      [[ -e $f ]] || continue
      ogrinfo -ro -al "$f" | sed "s|$dir/||g" >"$f.dump"
      rm "$f"
    done
  done
  jobs=$((jobs + 1))
  if diff -r -q "$work/ref/$name" "$work/new/$name" >/dev/null; then
    echo "same    $name"
  else
    echo "DIFFERS $name: geovor $*"
    diff -r -q "$work/ref/$name" "$work/new/$name" | sed 's/^/        /'
    failed=$((failed + 1))
  fi
}

for input in "$stations" "$cities" "$fixtures/tricky_ids.csv" "$fixtures/duplicate_ids.csv" \
             "$fixtures/near_duplicates.csv" "$fixtures/lon_180.csv" "$fixtures/quoted.csv" \
             "$fixtures/crlf_bom.csv" "$fixtures/bad_values.csv"; do
  base=$(basename "$input" .csv)
  for precision in "" 3 12; do
    p=(); [[ -n $precision ]] && p=(--precision "$precision")
    run_case "cells_${base}_p${precision}" cells "$input" -o cells.geojson "${p[@]}" --report rows.csv
    run_case "cells_${base}_seq_p${precision}" cells "$input" -o cells.geojsons "${p[@]}"
  done
  run_case "cells_${base}_geojsonl_t1" cells "$input" -o cells.geojsonl --threads 1
  run_case "cells_${base}_stdout_q" cells "$input" -o - -q
  run_case "cells_${base}_gpkg" cells "$input" -o cells.gpkg --report rows.csv
  run_case "cells_${base}_csv" cells "$input" -o cells.csv
  run_case "delaunay_${base}" delaunay "$input" -o triangles.geojson --edges edges.geojson
  run_case "delaunay_${base}_p3_noghosts" delaunay "$input" -o triangles.geojsons --edges edges.geojsonl --precision 3 --no-ghosts
  run_case "delaunay_${base}_gpkg" delaunay "$input" -o triangles.gpkg --edges edges.csv
  run_case "relax_${base}" relax "$input" -o relaxed.geojson -n 2 --sites-output sites.geojson
done
# Inputs in one hemisphere (ghost faces), a precision where cells collapse, GDAL-only options.
run_case "cells_stations_p1" cells "$stations" -o cells.geojson --precision 1 --report rows.csv
run_case "delaunay_stations_p1" delaunay "$stations" -o triangles.geojson --edges edges.geojson --precision 1
run_case "delaunay_stations_noghosts" delaunay "$stations" -o triangles.geojson --edges edges.geojson --no-ghosts
run_case "relax_stations_gpkg" relax "$stations" -o relaxed.gpkg -n 3 --relocation rebuild --sites-output sites.gpkg
run_case "relax_cities_p12" relax "$cities" -o relaxed.geojson -n 1 --precision 12 -q
run_case "cells_merge_m" cells "$stations" -o cells.geojson --merge-m 20000 --report rows.csv
run_case "cells_nonpoint" cells "$fixtures/non_point.geojson" -o cells.geojson
run_case "cells_empty" cells "$fixtures/empty.csv" -o cells.geojson
run_case "help_cells" cells --help
run_case "help_delaunay" delaunay --help
run_case "help_relax" relax --help
echo "$((jobs - failed)) of $jobs jobs identical ($work)"
((failed == 0))
