# Runs `geovor cells INPUT -o OUTPUT --overwrite -q` and checks the file with GDAL's ogrinfo, an
# independent reader: the feature count, no polygon invalid for GEOS, and a planar lon/lat area
# sum of 64800 square degrees (the cells tile the Earth, cut at +-180 and closed at the poles).
#
#   cmake -DGEOVOR=<exe> -DINPUT=<csv> -DOUTPUT=<file> -DCELLS=<n> [-DGEOM=<column>] [-DLAYER=<name>]
#         -P check_cells.cmake
# The layer is "cells", except in formats that name it after the file (GeoJSONSeq, Shapefile).
cmake_minimum_required(VERSION 3.25)
if(NOT DEFINED GEOM)
  set(GEOM GEOMETRY)
endif()
if(NOT DEFINED LAYER)
  set(LAYER cells)
endif()
execute_process(COMMAND ${GEOVOR} cells ${INPUT} -o ${OUTPUT} --overwrite -q
  RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "geovor cells exited ${rc}: ${err}")
endif()
include(${CMAKE_CURRENT_LIST_DIR}/ogr_sql.cmake)
ogr_sql(${OUTPUT} "SELECT COUNT(*) AS v FROM \"${LAYER}\"" count)
ogr_sql(${OUTPUT} "SELECT COUNT(*) AS v FROM \"${LAYER}\" WHERE NOT ST_IsValid(${GEOM})" invalid)
ogr_sql(${OUTPUT} "SELECT SUM(ST_Area(${GEOM})) AS v FROM \"${LAYER}\"" area)
set(failures)
if(NOT count EQUAL CELLS)
  list(APPEND failures "${count} cells, expected ${CELLS}")
endif()
if(NOT invalid EQUAL 0)
  list(APPEND failures "${invalid} polygons invalid for GEOS")
endif()
# CMake has no floats: compare the text of the sum.
if(NOT area MATCHES "^(64800(\\.0*[0-9]*)?|64799\\.99999[0-9]*)$")
  list(APPEND failures "planar area sum ${area}, expected 64800")
endif()
if(failures)
  message(FATAL_ERROR "${OUTPUT}: ${failures}")
endif()
message(STATUS "${OUTPUT}: ${count} valid cells, planar area ${area}")
