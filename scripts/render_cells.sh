#!/usr/bin/env bash
# Usage: scripts/render_cells.sh CELLS.gpkg OUT.png [WIDTH]
# Renders Voronoi cells written by `geovor cells` (GeoPackage layer "cells") as a PNG in plate
# carrée with GDAL's own tools only: each cell filled with a colour from its site_index, cell
# boundaries in dark grey, sites as black dots. Used for the picture in docs/user-guide.md.
set -euo pipefail
cells=$1 out=$2 width=${3:-2048}
height=$((width / 2))
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
box=(-te -180 -90 180 90 -ts "$width" "$height")
# Fill: site_index + 1 (0 stays the background), then a palette of pseudo-random pastel colours.
gdal_rasterize -q -a site_index -ot UInt32 -init 0 "${box[@]}" -l cells "$cells" "$tmp/fill.tif"
gdal_calc.py --quiet -A "$tmp/fill.tif" --outfile="$tmp/id.tif" --calc="A % 251 + 1" --type=Byte >/dev/null 2>&1 ||
  cp "$tmp/fill.tif" "$tmp/id.tif"
{
  echo "0 255 255 255"
  for i in $(seq 1 251); do
    echo "$i $((150 + (i * 37) % 100)) $((150 + (i * 59) % 100)) $((150 + (i * 83) % 100))"
  done
} >"$tmp/palette.txt"
gdaldem color-relief -q "$tmp/id.tif" "$tmp/palette.txt" "$tmp/rgb.tif"
# Boundaries and sites burnt on top.
ogr2ogr -q -f GPKG "$tmp/lines.gpkg" "$cells" -dialect SQLite -sql "SELECT ST_Boundary(geom) AS geom FROM cells" -nln lines
gdal_rasterize -q -b 1 -b 2 -b 3 -burn 90 -burn 90 -burn 90 -l lines "$tmp/lines.gpkg" "$tmp/rgb.tif"
ogr2ogr -q -f GPKG "$tmp/sites.gpkg" "$cells" -dialect SQLite \
  -sql "SELECT ST_Buffer(MakePoint(CAST(lon_deg AS REAL), CAST(lat_deg AS REAL), 4326), 0.25) AS geom FROM cells" -nln sites
gdal_rasterize -q -b 1 -b 2 -b 3 -burn 0 -burn 0 -burn 0 -l sites "$tmp/sites.gpkg" "$tmp/rgb.tif"
gdal_translate -q -of PNG "$tmp/rgb.tif" "$out"
