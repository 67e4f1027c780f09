# geovor is linked without GDAL and hands the jobs that need it to geovor-gdal (tools/main.cpp,
# run_geovor in tools/geovor.cpp). Every other CLI test runs geovor, so the OGR inputs and
# outputs there go through the hand-off; these check the split itself.
set(handoff_out ${CMAKE_CURRENT_BINARY_DIR}/handoff)
file(MAKE_DIRECTORY ${handoff_out})
# geovor does not load GDAL; geovor-gdal does.
geovor_cli_expect(cli.handoff.gdal_only_in_geovor_gdal 0 SCRIPT
  "readelf -d \"$0\" | grep -q NEEDED && ! readelf -d \"$0\" | grep -q libgdal && readelf -d $<TARGET_FILE:geovor_gdal_cli> | grep -q libgdal")
# A copy of geovor alone in a directory: it still runs a CSV -> GeoJSON job itself...
geovor_cli_expect(cli.handoff.alone_runs_geojson 0 SCRIPT
  "mkdir -p ${handoff_out}/alone && cp \"$0\" ${handoff_out}/alone/geovor && ${handoff_out}/alone/geovor cells ${fixtures}/three_sites.csv -o ${handoff_out}/alone/three.geojson --overwrite -q && grep -q FeatureCollection ${handoff_out}/alone/three.geojson")
# ...and says which executable it misses for a GeoPackage, with exit code 70.
geovor_cli_expect(cli.handoff.alone_misses_geovor_gdal 70 STDERR "needs GDAL.*no executable [^ ]*/lonely/geovor-gdal" SCRIPT
  "mkdir -p ${handoff_out}/lonely && cp \"$0\" ${handoff_out}/lonely/geovor && ${handoff_out}/lonely/geovor cells ${fixtures}/three_sites.csv -o ${handoff_out}/lonely/three.gpkg --overwrite -q")
geovor_cli_expect(cli.handoff.same_output 0 SCRIPT
  "\"$0\" cells datasets/weather_stations.csv -o ${handoff_out}/lean.geojson --overwrite -q 2>/dev/null && $<TARGET_FILE:geovor_gdal_cli> cells datasets/weather_stations.csv -o ${handoff_out}/full.geojson --overwrite -q 2>/dev/null && cmp ${handoff_out}/lean.geojson ${handoff_out}/full.geojson")
# An OGR input (info) and an OGR output beside a GeoJSON one (delaunay's edges) are handed on.
geovor_cli_expect(cli.handoff.info_ogr_input 0 STDOUT "sites: 3" SCRIPT
  "rm -f ${handoff_out}/three.gpkg && ogr2ogr -f GPKG ${handoff_out}/three.gpkg ${fixtures}/three_sites.csv -oo X_POSSIBLE_NAMES=lon* -oo Y_POSSIBLE_NAMES=lat* && \"$0\" info ${handoff_out}/three.gpkg")
geovor_cli_expect(cli.handoff.delaunay_ogr_edges 0 STDOUT "Feature Count: 3" SCRIPT
  "\"$0\" delaunay ${fixtures}/three_sites.csv -o ${handoff_out}/tri.geojson --edges ${handoff_out}/edges.fgb --overwrite -q && ogrinfo -so -al ${handoff_out}/edges.fgb")
