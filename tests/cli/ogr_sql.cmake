# ogr_sql(FILE QUERY OUT_VAR): runs QUERY (SQLite dialect) with GDAL's ogrinfo on FILE, an
# independent reader of what geovor wrote, and sets OUT_VAR to the value of the column named `v`
# of its first row; a failure of ogrinfo, or no such value, stops the script. Included by the
# check_*.cmake scripts (cmake -P).
function(ogr_sql file query out_var)
  execute_process(COMMAND ogrinfo -ro -q -dialect SQLite -sql "${query}" ${file}
    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0 OR NOT out MATCHES "v \\([A-Za-z0-9]+\\) = ([-0-9.eE+]+)")
    message(FATAL_ERROR "ogrinfo failed on '${query}' in ${file}: ${out} ${err}")
  endif()
  set(${out_var} ${CMAKE_MATCH_1} PARENT_SCOPE)
endfunction()

# check_cell_tiling(FILE LAYER GEOM CELLS FAILURES_VAR): the checks every cells file passes, read
# back by ogrinfo: CELLS features, none invalid for GEOS, and a planar lon/lat area sum of 64800
# square degrees (the cells tile the Earth, cut at +-180 and closed at the poles). Appends a
# message per failed check to the list FAILURES_VAR.
function(check_cell_tiling file layer geom cells failures_var)
  ogr_sql(${file} "SELECT COUNT(*) AS v FROM \"${layer}\"" count)
  ogr_sql(${file} "SELECT COUNT(*) AS v FROM \"${layer}\" WHERE NOT ST_IsValid(${geom})" invalid)
  ogr_sql(${file} "SELECT SUM(ST_Area(${geom})) AS v FROM \"${layer}\"" area)
  set(failures ${${failures_var}})
  if(NOT count EQUAL cells)
    list(APPEND failures "${count} cells, expected ${cells}")
  endif()
  if(NOT invalid EQUAL 0)
    list(APPEND failures "${invalid} polygons invalid for GEOS")
  endif()
  # CMake has no floats: compare the text of the sum.
  if(NOT area MATCHES "^(64800(\\.0*[0-9]*)?|64799\\.99999[0-9]*)$")
    list(APPEND failures "planar area sum ${area}, expected 64800")
  endif()
  set(${failures_var} ${failures} PARENT_SCOPE)
endfunction()
