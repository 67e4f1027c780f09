# Row accounting of one input (issue 5): every row read is a cell, merged into a cell, or rejected.
#
#   cmake -DGEOVOR=<exe> -DINPUT=<file> -DOUT=<dir> -DNAME=<name> -DROWS=<n> -DSITES=<n>
#         -DMERGED=<n> -DREJECTED=<n> [-DEXTRA=<arg|arg>] [-DCHECK_ROW_NUMBERS=ON] -P check_accounting.cmake
#
# The expected counts are worked out from the file by hand (see robustness_tests.cmake). Checks:
#  1. `geovor info INPUT` exits 0 and prints rows/sites/merged/rejected as expected, so
#     rows = sites + merged + rejected;
#  2. `geovor cells INPUT --report` exits 0; the GeoJSON has SITES features whose n_rows add up to
#     SITES + MERGED; the report has ROWS lines: SITES `site`, MERGED `merged`, REJECTED `rejected`;
#  3. with CHECK_ROW_NUMBERS, the report's row numbers are exactly 1..ROWS, each once (no row lost
#     or counted twice).
cmake_minimum_required(VERSION 3.25)
foreach(v GEOVOR INPUT OUT NAME ROWS SITES MERGED REJECTED)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "check_accounting.cmake: -D${v}=... is required")
  endif()
endforeach()
set(failures)
string(REPLACE "|" ";" EXTRA "${EXTRA}")

# 1. geovor info.
# No site: both commands stop with exit 3, listing the rejected rows, and write nothing.
if(SITES EQUAL 0)
  set(cells ${OUT}/${NAME}.geojson)
  set(report ${OUT}/${NAME}_report.csv)
  file(REMOVE ${cells} ${report})
  execute_process(COMMAND ${GEOVOR} info ${INPUT} ${EXTRA} RESULT_VARIABLE rc ERROR_VARIABLE err)
  string(REGEX MATCHALL "rejected: " listed "${err}")
  list(LENGTH listed n_listed)
  if(NOT rc EQUAL 3 OR NOT err MATCHES "no usable site \\(${ROWS} rows, ${REJECTED} rejected\\)" OR NOT n_listed EQUAL REJECTED)
    message(FATAL_ERROR "geovor info ${INPUT}: exit ${rc}, expected 3, no usable site and ${REJECTED} rows listed: ${err}")
  endif()
  execute_process(COMMAND ${GEOVOR} cells ${INPUT} -o ${cells} --report ${report} --overwrite -q ${EXTRA}
    RESULT_VARIABLE rc ERROR_VARIABLE err)
  if(NOT rc EQUAL 3 OR EXISTS ${cells} OR EXISTS ${report})
    message(FATAL_ERROR "geovor cells ${INPUT}: exit ${rc}, expected 3 and no output: ${err}")
  endif()
  message(STATUS "ok: no site, exit 3, nothing written")
  return()
endif()

execute_process(COMMAND ${GEOVOR} info ${INPUT} ${EXTRA} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "geovor info ${INPUT} exited ${rc}: ${err}")
endif()
foreach(key rows sites merged rejected)
  string(TOUPPER ${key} var)
  if(NOT out MATCHES "\n${key}: ([0-9]+)\n")
    list(APPEND failures "info prints no '${key}:' line")
    continue()
  endif()
  set(info_${key} ${CMAKE_MATCH_1})
  if(NOT info_${key} EQUAL ${var})
    list(APPEND failures "info: ${key} ${info_${key}}, expected ${${var}}")
  endif()
endforeach()
math(EXPR accounted "${info_sites} + ${info_merged} + ${info_rejected}")
if(NOT accounted EQUAL info_rows)
  list(APPEND failures "info: sites + merged + rejected = ${accounted}, rows ${info_rows}")
endif()

# 2. geovor cells with the row report.
set(cells ${OUT}/${NAME}.geojson)
set(report ${OUT}/${NAME}_report.csv)
file(REMOVE ${cells} ${report})
execute_process(COMMAND ${GEOVOR} cells ${INPUT} -o ${cells} --report ${report} --overwrite -q ${EXTRA}
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "geovor cells ${INPUT} exited ${rc}: ${err}")
endif()
file(READ ${cells} geojson)
string(REGEX MATCHALL "{\"type\":\"Feature\"" features "${geojson}")
list(LENGTH features n_features)
if(NOT n_features EQUAL SITES)
  list(APPEND failures "cells: ${n_features} features, expected ${SITES}")
endif()
string(REGEX MATCHALL "\"n_rows\":[0-9]+" n_rows "${geojson}")
set(sum_rows 0)
foreach(m IN LISTS n_rows)
  string(REPLACE "\"n_rows\":" "" k "${m}")
  math(EXPR sum_rows "${sum_rows} + ${k}")
endforeach()
math(EXPR expected_rows_in_cells "${SITES} + ${MERGED}")
if(NOT sum_rows EQUAL expected_rows_in_cells)
  list(APPEND failures "cells: n_rows add up to ${sum_rows}, expected sites + merged = ${expected_rows_in_cells}")
endif()
set(geojson)

# The report: one line per row, `row,line,id,status,site_index,detail`; ids and details are
# quoted, and may hold commas or line breaks, so the status is found after the first two numbers
# and a quoted id (or none, for a rejected row).
file(READ ${report} text)
if(NOT text MATCHES "^row,line,id,status,site_index,detail\n")
  list(APPEND failures "report: no header")
endif()
set(record "\n([0-9]+),[0-9]+,(\"([^\"]|\"\")*\")?,(site|merged|rejected),")
string(REGEX MATCHALL "${record}" records "${text}")
list(LENGTH records n_records)
string(REGEX MATCHALL "\",site," s "${text}")
string(REGEX MATCHALL "\",merged," m "${text}")
string(REGEX MATCHALL "\n[0-9]+,[0-9]+,,rejected," r "${text}")
list(LENGTH s n_site)
list(LENGTH m n_merged)
list(LENGTH r n_rejected)
foreach(pair "n_records;ROWS" "n_site;SITES" "n_merged;MERGED" "n_rejected;REJECTED")
  list(GET pair 0 got)
  list(GET pair 1 want)
  if(NOT ${got} EQUAL ${${want}})
    list(APPEND failures "report: ${got} ${${got}}, expected ${${want}}")
  endif()
endforeach()

# 3. Every row number once.
if(CHECK_ROW_NUMBERS)
  set(rows)
  foreach(rec IN LISTS records)
    string(REGEX REPLACE "^\n([0-9]+),.*" "\\1" row "${rec}")
    list(APPEND rows ${row})
  endforeach()
  list(SORT rows COMPARE NATURAL)
  set(expected)
  if(ROWS GREATER 0)
    foreach(i RANGE 1 ${ROWS})
      list(APPEND expected ${i})
    endforeach()
  endif()
  if(NOT "${rows}" STREQUAL "${expected}")
    list(APPEND failures "report: row numbers ${rows}, expected 1..${ROWS} each once")
  endif()
endif()

if(failures)
  list(JOIN failures "\n  " text)
  message(FATAL_ERROR "${INPUT}:\n  ${text}")
endif()
message(STATUS "${INPUT}: ${info_rows} rows = ${info_sites} cells + ${info_merged} merged + ${info_rejected} rejected")
