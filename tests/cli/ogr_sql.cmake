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
