# Runs `geovor relax INPUT -o OUTPUT -n ITERATIONS --sites-output SITES --overwrite [ARGS]` and
# checks: exit 0; one stderr line per iteration with an energy strictly below the previous one
# and a final energy below the last; then, with GDAL's ogrinfo (an independent reader), CELLS
# features in OUTPUT, none invalid for GEOS, a planar lon/lat area sum of 64800 square degrees
# (the cells tile the Earth), and CELLS points in SITES.
#
#   cmake -DGEOVOR=<exe> -DINPUT=<file> -DOUTPUT=<file> -DSITES=<file> -DCELLS=<n> -DITERATIONS=<n>
#         [-DARGS=<a|b>] [-DLAYER=<cells layer>] [-DSITES_LAYER=<sites layer>] [-DGEOM=<column>]
#         -P check_relax.cmake
cmake_minimum_required(VERSION 3.25)
string(REPLACE "|" ";" ARGS "${ARGS}")
if(NOT DEFINED GEOM)
  set(GEOM GEOMETRY)
  if(OUTPUT MATCHES "\\.gpkg$")
    set(GEOM geom)
  endif()
endif()
if(NOT DEFINED LAYER)
  set(LAYER cells)
endif()
if(NOT DEFINED SITES_LAYER)
  set(SITES_LAYER sites)
endif()
execute_process(COMMAND ${GEOVOR} relax ${INPUT} -o ${OUTPUT} -n ${ITERATIONS} --sites-output ${SITES} --overwrite ${ARGS}
  RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "geovor relax exited ${rc}: ${err}")
endif()
set(failures)
# Iteration lines: "<iteration> <energy> <max_move_m> ..." (CMake's LESS compares as doubles).
string(REGEX MATCHALL "\n +[0-9]+ +[0-9.eE+-]+ " lines "${err}")
list(LENGTH lines n)
if(NOT n EQUAL ITERATIONS)
  list(APPEND failures "${n} iteration lines, expected ${ITERATIONS}")
endif()
set(previous "")
foreach(line IN LISTS lines)
  string(REGEX REPLACE "\n +[0-9]+ +([0-9.eE+-]+) " "\\1" energy "${line}")
  if(NOT previous STREQUAL "" AND NOT energy LESS previous)
    list(APPEND failures "energy ${energy} not below ${previous}")
  endif()
  set(previous ${energy})
endforeach()
if(NOT err MATCHES "final energy ([0-9.eE+-]+)")
  list(APPEND failures "no final energy line")
elseif(NOT previous STREQUAL "" AND NOT CMAKE_MATCH_1 LESS previous)
  list(APPEND failures "final energy ${CMAKE_MATCH_1} not below ${previous}")
endif()

include(${CMAKE_CURRENT_LIST_DIR}/ogr_sql.cmake)
check_cell_tiling(${OUTPUT} ${LAYER} ${GEOM} ${CELLS} failures)
ogr_sql(${SITES} "SELECT COUNT(*) AS v FROM \"${SITES_LAYER}\"" sites)
if(NOT sites EQUAL CELLS)
  list(APPEND failures "${sites} sites, expected ${CELLS}")
endif()
if(failures)
  message(FATAL_ERROR "${OUTPUT}: ${failures}\n${err}")
endif()
message(STATUS "${OUTPUT}: ${n} iterations, energy decreasing, ${CELLS} valid cells, ${sites} sites")
