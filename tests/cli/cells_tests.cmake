# CLI tests of `geovor cells` (included by tests/cli/CMakeLists.txt): every output format read
# back by GDAL (check_cells.cmake), the degenerate fixtures, refusal to overwrite, the row report.
set(check_cells ${CMAKE_CURRENT_SOURCE_DIR}/check_cells.cmake)
set(cells_out ${CMAKE_CURRENT_BINARY_DIR}/cells)
file(MAKE_DIRECTORY ${cells_out})

# geovor_cli_cells(name input cells output [geometry column [layer]])
function(geovor_cli_cells name input cells output)
  set(geom GEOMETRY)
  set(layer cells)
  if(ARGC GREATER 4)
    set(geom ${ARGV4})
  endif()
  if(ARGC GREATER 5)
    set(layer ${ARGV5})
  endif()
  add_test(NAME cli.cells.${name}
    COMMAND ${CMAKE_COMMAND} -DGEOVOR=$<TARGET_FILE:geovor_cli> -DINPUT=${input}
            -DOUTPUT=${cells_out}/${output} -DCELLS=${cells} -DGEOM=${geom} -DLAYER=${layer} -P ${check_cells}
    WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
  set_tests_properties(cli.cells.${name} PROPERTIES LABELS cli)
endfunction()

geovor_cli_cells(weather_geojson datasets/weather_stations.csv 5631 weather.geojson)
geovor_cli_cells(weather_geojsonseq datasets/weather_stations.csv 5631 weather.geojsonl GEOMETRY weather)
geovor_cli_cells(weather_gpkg datasets/weather_stations.csv 5631 weather.gpkg geom)
geovor_cli_cells(weather_fgb datasets/weather_stations.csv 5631 weather.fgb)
geovor_cli_cells(weather_shp datasets/weather_stations.csv 5631 weather.shp GEOMETRY weather)
# Degenerate inputs: one site (the whole Earth), two (hemispheres), three, a great circle (lunes),
# a small circle, one hemisphere, the cube, duplicates, the antimeridian, the poles.
geovor_cli_cells(one_site ${fixtures}/one_site.csv 1 one_site.geojson)
geovor_cli_cells(two_sites ${fixtures}/two_sites.csv 2 two_sites.geojson)
geovor_cli_cells(three_sites ${fixtures}/three_sites.csv 3 three_sites.geojson)
geovor_cli_cells(equator ${fixtures}/equator.csv 12 equator.geojson)
geovor_cli_cells(small_circle ${fixtures}/small_circle.csv 12 small_circle.geojson)
geovor_cli_cells(hemisphere ${fixtures}/hemisphere.csv 20 hemisphere.geojson)
geovor_cli_cells(cube_corners ${fixtures}/cube_corners.csv 8 cube_corners.geojson)
geovor_cli_cells(duplicates ${fixtures}/duplicates.csv 3 duplicates.geojson)
geovor_cli_cells(antimeridian ${fixtures}/antimeridian.csv 8 antimeridian.geojson)
geovor_cli_cells(poles ${fixtures}/poles.csv 10 poles.geojson)

# An existing output is refused (exit 4) without --overwrite.
file(WRITE ${cells_out}/exists.geojson "keep me")
geovor_cli_expect(cli.cells.refuses_existing 4 STDERR "exists.*--overwrite"
  COMMAND cells ${fixtures}/three_sites.csv -o ${cells_out}/exists.geojson)
# With --overwrite an existing GeoJSON output is replaced (it is removed while the triangulation
# is built), also when it was the input: a point layer read through GDAL, then its cells.
geovor_cli_expect(cli.cells.overwrites_existing 0 SCRIPT
  "printf 'old contents' > ${cells_out}/replaced.geojson && \"$0\" cells ${fixtures}/three_sites.csv -o ${cells_out}/replaced.geojson --overwrite -q && grep -q FeatureCollection ${cells_out}/replaced.geojson && ! grep -q 'old contents' ${cells_out}/replaced.geojson")
geovor_cli_expect(cli.cells.output_was_the_input 0 STDOUT "Feature Count: 3.*MULTIPOLYGON" SCRIPT
  "rm -f ${cells_out}/in_out.geojson && ogr2ogr -f GeoJSON ${cells_out}/in_out.geojson ${fixtures}/three_sites.csv -oo X_POSSIBLE_NAMES=lon* -oo Y_POSSIBLE_NAMES=lat* && \"$0\" cells ${cells_out}/in_out.geojson -o ${cells_out}/in_out.geojson --overwrite -q && ogrinfo -al -so ${cells_out}/in_out.geojson && ogrinfo -al ${cells_out}/in_out.geojson | grep -m1 MULTIPOLYGON")
# The row report accounts for every row: bad_rows.csv has 4 sites and 8 rejected rows.
geovor_cli_expect(cli.cells.report 0
  COMMAND cells ${fixtures}/bad_rows.csv -o ${cells_out}/bad_rows.geojson --overwrite -q
          --report ${cells_out}/bad_rows_report.csv)
# 4 site lines then 8 rejected lines (CMake regexes have no {n}).
set(site_line "[^\n]*,site,[^\n]*\n")
set(rejected_line "[^\n]*,rejected,[^\n]*\n")
string(REPEAT "${site_line}" 4 four_sites)
string(REPEAT "${rejected_line}" 8 eight_rejected)
set(report_regex "row,line,id,status,site_index,detail\n${four_sites}${eight_rejected}")
add_test(NAME cli.cells.report.rows
  COMMAND ${CMAKE_COMMAND} -E cat ${cells_out}/bad_rows_report.csv)
set_tests_properties(cli.cells.report.rows PROPERTIES LABELS cli DEPENDS cli.cells.report
  PASS_REGULAR_EXPRESSION "${report_regex}")
# Ids with quotes, backslashes, control characters and non-ASCII letters, and a merged row: the
# GeoJSON outputs' id fields (escaped ahead, twice in the lists) read back by GDAL as the
# GeoPackage's (written as values).
add_test(NAME cli.cells.tricky_ids
  COMMAND ${CMAKE_COMMAND} -DGEOVOR=$<TARGET_FILE:geovor_cli> -DINPUT=tests/cli/fixtures/tricky_ids.csv
          -DOUT=${cells_out} -P ${CMAKE_CURRENT_SOURCE_DIR}/check_id_texts.cmake
  WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
set_tests_properties(cli.cells.tricky_ids PROPERTIES LABELS cli)
# --quiet drops the list of merged rows (they are in the cells' ids) but never the rejected rows.
geovor_cli_expect(cli.cells.quiet_keeps_rejections 0 STDOUT "^merged 0 rejected 8\n$" SCRIPT
  "\"$0\" cells ${fixtures}/duplicates.csv -o ${cells_out}/quiet_dup.geojson --overwrite -q 2>${cells_out}/quiet_dup.err && \"$0\" cells ${fixtures}/bad_rows.csv -o ${cells_out}/quiet_bad.geojson --overwrite -q 2>${cells_out}/quiet_bad.err && echo merged $(grep -c 'merged into' ${cells_out}/quiet_dup.err) rejected $(grep -c rejected ${cells_out}/quiet_bad.err)")
geovor_cli_expect(cli.cells.lists_merges 0 STDERR "row 2 .id 2. merged into the site of row 1 .id 1.: same position"
  COMMAND cells ${fixtures}/duplicates.csv -o ${cells_out}/loud_dup.geojson --overwrite)
# geovor cells --clip (issue 35): the stations cut by Natural Earth's countries against brute
# force, GEOS and geographiclib, the weights table, threads, CRS, the Python package, bad regions
# (tests/cli/clip_test.py).
add_test(NAME cli.cells.clip_to_regions
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/clip_test.py $<TARGET_FILE:geovor_cli> ${CMAKE_CURRENT_BINARY_DIR}/clip
          $<$<TARGET_EXISTS:_geovor>:$<TARGET_FILE:_geovor>>)
set_tests_properties(cli.cells.clip_to_regions PROPERTIES LABELS "cli" TIMEOUT 300)
