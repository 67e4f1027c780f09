# ogr2ogr's output model (issue 16): -f/--format, --nln, --update, --overwrite, --lco, --dsco;
# the triangles and edges of `geovor delaunay` as two layers of one GeoPackage. GDAL's ogrinfo
# reads back the layers, their names and counts. hemisphere.csv: 20 sites, no merge, so 20 cells,
# 2 * 20 - 4 = 36 triangles and 3 * 20 - 6 = 54 edges (ghosts included).
set(om ${CMAKE_CURRENT_BINARY_DIR}/output_model)
file(MAKE_DIRECTORY ${om} ${om}/failed)
set(hemi ${PROJECT_SOURCE_DIR}/${fixtures}/hemisphere.csv)
# A GeoPackage with one point layer `stations` (20 features), as QGIS or ogr2ogr would make it.
set(make_stations "rm -f STATIONS && ogr2ogr -f GPKG STATIONS ${hemi} -oo X_POSSIBLE_NAMES=lon* -oo Y_POSSIBLE_NAMES=lat* -nln stations")
function(stations_gpkg out_var path)
  string(REPLACE "STATIONS" "${path}" cmd "${make_stations}")
  set(${out_var} "${cmd}" PARENT_SCOPE)
endfunction()
set(count "ogrinfo -ro -q -sql")  # + "SELECT COUNT(*) AS v FROM layer" FILE

# --overwrite on an existing GeoPackage replaces the named layer only: the input layer stays.
# Before: the whole file was replaced, the stations lost.
stations_gpkg(mk ${om}/overwrite.gpkg)
geovor_cli_expect(cli.output_model.overwrite_keeps_other_layers 0
  STDOUT "^1: stations \\(Point\\)\n2: cells \\(Multi Polygon\\)\n.*v \\(Integer\\) = 20\n.*v \\(Integer\\) = 20\n" SCRIPT
  "${mk} && \"$0\" cells ${om}/overwrite.gpkg -o ${om}/overwrite.gpkg --overwrite -q && \"$0\" cells ${om}/overwrite.gpkg --layer stations -o ${om}/overwrite.gpkg --overwrite -q && ogrinfo -ro -q ${om}/overwrite.gpkg && ${count} 'SELECT COUNT(*) AS v FROM stations' ${om}/overwrite.gpkg && ${count} 'SELECT COUNT(*) AS v FROM cells' ${om}/overwrite.gpkg")

# --update --nln adds a layer beside the others; an existing data source without --update or
# --overwrite is refused, naming both.
stations_gpkg(mk ${om}/update.gpkg)
geovor_cli_expect(cli.output_model.update_adds_layer 0
  STDOUT "^1: stations \\(Point\\)\n2: voronoi \\(Multi Polygon\\)\n.*v \\(Integer\\) = 20\n" SCRIPT
  "${mk} && \"$0\" cells ${om}/update.gpkg -o ${om}/update.gpkg --update --nln voronoi -q && ogrinfo -ro -q ${om}/update.gpkg && ${count} 'SELECT COUNT(*) AS v FROM voronoi' ${om}/update.gpkg")
stations_gpkg(mk ${om}/refused.gpkg)
geovor_cli_expect(cli.output_model.existing_refused 4
  STDERR "refused\\.gpkg: exists; use --overwrite to replace it \\(its layer of that name only\\), or --update to add a layer" SCRIPT
  "${mk} && cp ${om}/refused.gpkg ${om}/refused.orig && \"$0\" cells ${hemi} -o ${om}/refused.gpkg -q\nrc=$?\ncmp ${om}/refused.gpkg ${om}/refused.orig || exit 99\nexit $rc")
# --update onto a layer of the same name: refused (exit 4), the file as it was.
stations_gpkg(mk ${om}/same_layer.gpkg)
geovor_cli_expect(cli.output_model.update_same_layer_refused 4
  STDERR "same_layer\\.gpkg: has a layer 'stations'; use --overwrite to replace it" SCRIPT
  "${mk} && cp ${om}/same_layer.gpkg ${om}/same_layer.orig && \"$0\" cells ${hemi} -o ${om}/same_layer.gpkg --update --nln stations -q\nrc=$?\ncmp ${om}/same_layer.gpkg ${om}/same_layer.orig || exit 99\nexit $rc")
# --update of a missing data source creates it.
geovor_cli_expect(cli.output_model.update_creates 0 STDOUT "^1: cells \\(Multi Polygon\\)\n$" SCRIPT
  "rm -f ${om}/created.gpkg && \"$0\" cells ${hemi} -o ${om}/created.gpkg --update -q && ogrinfo -ro -q ${om}/created.gpkg")

# A failure while updating leaves the data source as it was, every layer included: the layer is
# written into a copy that replaces the original only once complete. Here the replaced layer
# `cells` is deleted in the copy, then its new table cannot be made (its geometry column named
# like a field: GDAL fails at the first feature) or a field cannot be (a text FID); the original
# is byte for byte the same, and no temporary is left.
set(fd ${om}/failed)  # its own folder: nothing but the two files may be left there
stations_gpkg(mk ${fd}/failed.gpkg)
geovor_cli_expect(cli.output_model.update_failure_keeps_layers 4 STDERR "failed\\.gpkg: cannot write feature 1" SCRIPT
  "rm -f ${fd}/* && ${mk} && \"$0\" cells ${fd}/failed.gpkg -o ${fd}/failed.gpkg --update -q && cp ${fd}/failed.gpkg ${fd}/failed.orig && \"$0\" cells ${fd}/failed.gpkg --layer stations -o ${fd}/failed.gpkg --update --overwrite -q --lco GEOMETRY_NAME=site_id\nrc=$?\ncmp ${fd}/failed.gpkg ${fd}/failed.orig || exit 99\ntest \"$(ls -A ${fd} | tr '\\n' ' ')\" = 'failed.gpkg failed.orig ' || exit 98\nexit $rc")
geovor_cli_expect(cli.output_model.update_failure_keeps_layers_field 2 STDERR "failed2\\.gpkg: format GPKG cannot hold the field 'site_id'" SCRIPT
  "rm -f ${om}/failed2.gpkg && \"$0\" cells ${hemi} -o ${om}/failed2.gpkg -q && \"$0\" delaunay ${hemi} -o ${om}/failed2.gpkg --nln tri --update -q && cp ${om}/failed2.gpkg ${om}/failed2.orig && \"$0\" cells ${hemi} -o ${om}/failed2.gpkg --overwrite -q --lco FID=site_id\nrc=$?\ncmp ${om}/failed2.gpkg ${om}/failed2.orig || exit 99\nexit $rc")

# delaunay: triangles and edges into one GeoPackage, two layers (default names, or --nln and
# --edges-nln), with every feature.
geovor_cli_expect(cli.output_model.delaunay_one_gpkg 0
  STDOUT "^1: triangles \\(Multi Polygon\\)\n2: edges \\(Multi Line String\\)\n.*v \\(Integer\\) = 36\n.*v \\(Integer\\) = 54\n" SCRIPT
  "rm -f ${om}/tin.gpkg && \"$0\" delaunay ${hemi} -o ${om}/tin.gpkg --edges ${om}/tin.gpkg -q && ogrinfo -ro -q ${om}/tin.gpkg && ${count} 'SELECT COUNT(*) AS v FROM triangles' ${om}/tin.gpkg && ${count} 'SELECT COUNT(*) AS v FROM edges' ${om}/tin.gpkg")
geovor_cli_expect(cli.output_model.delaunay_layer_names 0
  STDOUT "^1: tri \\(Multi Polygon\\)\n2: edg \\(Multi Line String\\)\n$" SCRIPT
  "rm -f ${om}/named.gpkg && \"$0\" delaunay ${hemi} -o ${om}/named.gpkg --edges ${om}/../output_model/named.gpkg --nln tri --edges-nln edg -q && ogrinfo -ro -q ${om}/named.gpkg")
geovor_cli_expect(cli.output_model.delaunay_same_layer_names 2 STDERR "two layers named 'x'"
  COMMAND delaunay ${hemi} -o ${om}/twice.gpkg --edges ${om}/twice.gpkg --nln x --edges-nln x --overwrite -q)
# A one-layer format cannot take both: the same file is refused before any work (exit 2).
geovor_cli_expect(cli.output_model.delaunay_one_fgb 2 STDERR "--output [^\n]*one\\.fgb and --edges [^\n]*one\\.fgb are the same file"
  COMMAND delaunay ${hemi} -o ${om}/one.fgb --edges ${om}/one.fgb -q)
# relax: the final sites as a second layer of the cells' GeoPackage.
geovor_cli_expect(cli.output_model.relax_sites_layer 0
  STDOUT "^1: cells \\(Multi Polygon\\)\n2: sites \\(Point\\)\n.*v \\(Integer\\) = 20\n" SCRIPT
  "rm -f ${om}/relax.gpkg && \"$0\" relax ${hemi} -o ${om}/relax.gpkg --sites-output ${om}/relax.gpkg -n 2 -q && ogrinfo -ro -q ${om}/relax.gpkg && ${count} 'SELECT COUNT(*) AS v FROM sites' ${om}/relax.gpkg")

# -f is --format; --nln names the layer.
geovor_cli_expect(cli.output_model.f_and_nln 0 STDOUT "^1: voronoi \\(Multi Polygon\\)\n$" SCRIPT
  "rm -f ${om}/cells.dat && \"$0\" cells ${hemi} -o ${om}/cells.dat -f GPKG --nln voronoi -q 2>/dev/null && ogrinfo -ro -q ${om}/cells.dat 2>/dev/null")
# --lco and --dsco reach GDAL: the geometry column's name, and no gpkg_ogr_contents table.
geovor_cli_expect(cli.output_model.lco_dsco 0 STDOUT "Geometry Column = shape\n.*v \\(Integer\\) = 0\n" SCRIPT
  "rm -f ${om}/options.gpkg && \"$0\" cells ${hemi} -o ${om}/options.gpkg --lco GEOMETRY_NAME=shape --dsco ADD_GPKG_OGR_CONTENTS=NO -q && ogrinfo -ro -so ${om}/options.gpkg cells && ${count} \"SELECT COUNT(*) AS v FROM sqlite_master WHERE name = 'gpkg_ogr_contents'\" ${om}/options.gpkg")
geovor_cli_expect(cli.output_model.lco_syntax 2 STDERR "--lco: expected NAME=VALUE, got 'GEOMETRY_NAME'"
  COMMAND cells ${hemi} -o ${om}/syntax.gpkg --lco GEOMETRY_NAME -q)
# GeoJSON is written by geovor itself, one layer: --update and --lco are refused (exit 2).
geovor_cli_expect(cli.output_model.geojson_update 2 STDERR "c\\.geojson: --update adds a layer to a data source that holds several"
  COMMAND cells ${hemi} -o ${om}/c.geojson --update -q)
geovor_cli_expect(cli.output_model.geojson_lco 2 STDERR "c\\.geojson: --lco and --dsco are GDAL creation options"
  COMMAND cells ${hemi} -o ${om}/c.geojson --lco RFC7946=YES -q)
geovor_cli_expect(cli.output_model.shapefile_update 2 STDERR "--update adds a layer to a data source that holds several [^\n]*ESRI Shapefile holds one"
  COMMAND cells ${hemi} -o ${om}/c.shp --update -q)
# delaunay's options concern the outputs they can: --update and --lco the GeoPackage of the
# triangles, not the GeoJSON edges beside it (written as without them).
geovor_cli_expect(cli.output_model.delaunay_mixed_outputs 0
  STDOUT "^1: triangles \\(Multi Polygon\\)\n.*Geometry Column = shape\n.*Feature Count: 54\n" SCRIPT
  "rm -f ${om}/mixed.gpkg ${om}/mixed_edges.geojson && \"$0\" delaunay ${hemi} -o ${om}/mixed.gpkg --edges ${om}/mixed_edges.geojson --update --lco GEOMETRY_NAME=shape -q && ogrinfo -ro -q ${om}/mixed.gpkg && ogrinfo -ro -so ${om}/mixed.gpkg triangles && ogrinfo -ro -so -al ${om}/mixed_edges.geojson")
