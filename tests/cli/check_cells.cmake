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
set(failures)
check_cell_tiling(${OUTPUT} ${LAYER} ${GEOM} ${CELLS} failures)
if(failures)
  message(FATAL_ERROR "${OUTPUT}: ${failures}")
endif()
message(STATUS "${OUTPUT}: ${CELLS} valid cells tiling the Earth")
