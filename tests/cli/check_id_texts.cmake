# cmake -DGEOVOR=... -DINPUT=... -DOUT=dir -P check_id_texts.cmake: the GeoJSON writer takes the
# ids, ids lists and neighbour lists as text escaped ahead (geovor cells), the GeoPackage writer
# as values (through GDAL); GDAL's own GeoJSON reader must read back from the .geojson, the
# .geojsons and stdout exactly the values it reads from the .gpkg (ids and neighbors: JSON text of
# the JSON subtype in the GeoPackage, arrays in GeoJSON, which GDAL reads as JSON text with
# ARRAY_AS_STRING=YES, spaced as json-c spaces it; GeoJSONSeq, which lacks that option, reads back
# the lists the .geojson has).
function(run_geovor)
  execute_process(COMMAND ${GEOVOR} cells ${INPUT} ${ARGN} --overwrite -q RESULT_VARIABLE rc ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "geovor cells ${INPUT} ${ARGN} failed (${rc}): ${err}")
  endif()
endfunction()
# The id-bearing fields of every cell as ogrinfo prints them, in site order.
function(id_fields file layer out_var)
  execute_process(COMMAND ogrinfo -ro -q ${ARGN} -dialect SQLite
    -sql "SELECT site_index, site_id, ids, n_rows, neighbors FROM \"${layer}\" ORDER BY site_index" ${file}
    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "ogrinfo failed on ${file}: ${err}")
  endif()
  string(REGEX REPLACE "OGRFeature\\([^)]*\\)" "OGRFeature" out "${out}")  # layer names differ
  string(REPLACE "(Integer64)" "(Integer)" out "${out}")  # GeoJSON reads small integers as Integer
  string(REPLACE "(String(JSON))" "(String)" out "${out}")
  string(REPLACE "= [ " "= [" out "${out}")  # json-c's spacing of the GeoJSON arrays
  string(REPLACE "\", \"" "\",\"" out "${out}")
  string(REPLACE "\" ]" "\"]" out "${out}")
  string(STRIP "${out}" out)
  set(${out_var} "${out}" PARENT_SCOPE)
endfunction()

run_geovor(-o ${OUT}/tricky_ids.gpkg)
run_geovor(-o ${OUT}/tricky_ids.geojson)
run_geovor(-o ${OUT}/tricky_ids.geojsons)
execute_process(COMMAND ${GEOVOR} cells ${INPUT} -o - -q OUTPUT_FILE ${OUT}/tricky_ids_stdout.geojson RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "geovor cells ${INPUT} -o - failed (${rc})")
endif()
id_fields(${OUT}/tricky_ids.gpkg cells expected)
# Sanity: the values GDAL reads from the GeoPackage are the ids as append_json_string writes them.
foreach(piece "q\\\"uote" "back\\\\slash" "tab\\tid" "new\\nline" "Zürich" "dup\\\"2\\\\\"")
  string(FIND "${expected}" "${piece}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "${piece} not in the GeoPackage's id fields:\n${expected}")
  endif()
endforeach()
foreach(file tricky_ids.geojson tricky_ids_stdout.geojson)
  id_fields(${OUT}/${file} cells got -oo ARRAY_AS_STRING=YES)
  if(NOT got STREQUAL expected)
    message(FATAL_ERROR "${file} reads back other id fields than the GeoPackage:\n${got}\nexpected:\n${expected}")
  endif()
endforeach()
id_fields(${OUT}/tricky_ids.geojson cells lists)
id_fields(${OUT}/tricky_ids.geojsons tricky_ids got)
if(NOT got STREQUAL lists)
  message(FATAL_ERROR "tricky_ids.geojsons reads back other id fields than the .geojson:\n${got}\nexpected:\n${lists}")
endif()
