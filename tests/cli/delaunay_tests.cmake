# CLI tests of `geovor delaunay` (included by tests/cli/CMakeLists.txt): triangles and edges in
# every format read back by GDAL (check_delaunay.cmake), degenerate fixtures, usage errors.
set(check_delaunay ${CMAKE_CURRENT_SOURCE_DIR}/check_delaunay.cmake)
set(delaunay_out ${CMAKE_CURRENT_BINARY_DIR}/delaunay)
file(MAKE_DIRECTORY ${delaunay_out})

# geovor_cli_delaunay(name input ext triangles edges ghosts [AREA_KM2 n|skip] [GEOM column]
#                     [TLAYER l] [ELAYER l] [HULL n] [ARGS ...])
function(geovor_cli_delaunay name input ext ntri nedges ghosts)
  cmake_parse_arguments(ARG "" "AREA_KM2;GEOM;TLAYER;ELAYER;HULL" "ARGS" ${ARGN})
  set(defs)
  foreach(v AREA_KM2 GEOM TLAYER ELAYER HULL)
    if(ARG_${v})
      list(APPEND defs -D${v}=${ARG_${v}})
    endif()
  endforeach()
  string(REPLACE ";" "|" args "${ARG_ARGS}")  # a list cannot cross the command line
  add_test(NAME cli.delaunay.${name}
    COMMAND ${CMAKE_COMMAND} -DGEOVOR=$<TARGET_FILE:geovor_cli> -DINPUT=${input}
            -DTRIANGLES=${delaunay_out}/${name}_triangles.${ext} -DEDGES=${delaunay_out}/${name}_edges.${ext}
            -DNTRI=${ntri} -DNEDGES=${nedges} -DGHOSTS=${ghosts} ${defs} "-DARGS=${args}" -P ${check_delaunay}
    WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
  set_tests_properties(cli.delaunay.${name} PROPERTIES LABELS cli)
endfunction()

# 5631 sites (5634 rows, 3 merged): 2n - 4 triangles, 3n - 6 edges. The South Pole station is
# 0.17 m from the pole.
geovor_cli_delaunay(weather_geojson datasets/weather_stations.csv geojson 11258 16887 0)
geovor_cli_delaunay(weather_gpkg datasets/weather_stations.csv gpkg 11258 16887 0 GEOM geom)
geovor_cli_delaunay(weather_fgb datasets/weather_stations.csv fgb 11258 16887 0)
geovor_cli_delaunay(weather_shp datasets/weather_stations.csv shp 11258 16887 0
  TLAYER weather_shp_triangles ELAYER weather_shp_edges)
# Degenerate inputs: the antimeridian, the poles, the cube, three sites (one proper face and one
# ghost), one hemisphere (ghost faces, and without them), all on the equator (hemispheres).
# Sites at +-179.9999999 make triangles 1e-7 degrees wide at the cut: 7 decimals would flatten
# them (GEOS-invalid), so this one is written with 12 (and in GeoPackage, with doubles).
geovor_cli_delaunay(antimeridian ${fixtures}/antimeridian.csv geojson 12 18 0 ARGS --precision 12)
geovor_cli_delaunay(antimeridian_gpkg ${fixtures}/antimeridian.csv gpkg 12 18 0 GEOM geom)
geovor_cli_delaunay(poles ${fixtures}/poles.csv geojson 16 24 0)
geovor_cli_delaunay(cube_corners ${fixtures}/cube_corners.csv geojson 12 18 0)
geovor_cli_delaunay(three_sites ${fixtures}/three_sites.csv geojson 2 3 1 AREA_KM2 skip HULL 3)
geovor_cli_delaunay(hemisphere ${fixtures}/hemisphere.csv geojson 36 54 8 AREA_KM2 skip HULL 10)
# --no-ghosts also leaves out the 7 edges between two ghost faces (diagonals of the decagon at
# lat 20 seen from outside).
geovor_cli_delaunay(hemisphere_no_ghosts ${fixtures}/hemisphere.csv geojson 28 47 0 AREA_KM2 skip HULL 10
  ARGS --no-ghosts)
# Issue 14: a hull of 4 sites around a fifth. The two ghost faces share the diagonal b-e, which
# is neither a hull edge nor written with --no-ghosts.
geovor_cli_delaunay(hull_crossing ${fixtures}/hull_crossing.csv geojson 6 9 2 AREA_KM2 skip HULL 4)
geovor_cli_delaunay(hull_crossing_no_ghosts ${fixtures}/hull_crossing.csv geojson 4 8 0 AREA_KM2 skip HULL 4
  ARGS --no-ghosts)
# 4 sites on the equator and one north: the two great-circle faces of the equator polygon and one
# ghost are outside the hull (ghost = 1); the hull is the fan of 3 proper triangles from the north
# site, bounded by 5 edges.
geovor_cli_delaunay(hull_on_great_circle ${fixtures}/hull_on_great_circle.csv geojson 6 9 3 AREA_KM2 skip HULL 5)
geovor_cli_delaunay(hull_on_great_circle_no_ghosts ${fixtures}/hull_on_great_circle.csv geojson 3 7 0
  AREA_KM2 skip HULL 5 ARGS --no-ghosts)
# Issue 14: thin triangles (sites 0.001 degrees apart on latitudes 60 and -30, two sites 0.44 and
# 0.89 m from the north pole) are written non-empty and valid in doubles and with 17 decimals
# (their sides bulge by 0.4 mm from a lon/lat row: 7 decimals cannot show them).
geovor_cli_delaunay(thin_triangles ${fixtures}/thin_triangles.csv geojson 22 33 0 ARGS --precision 17)
geovor_cli_delaunay(thin_triangles_gpkg ${fixtures}/thin_triangles.csv gpkg 22 33 0 GEOM geom)
# 12 sites on the equator: 20 faces, each a hemisphere (10 ellipsoids in all).
geovor_cli_delaunay(equator ${fixtures}/equator.csv geojson 20 30 0 AREA_KM2 5100656217)

# Nothing to write is a usage error; an existing output is refused without --overwrite.
geovor_cli_expect(cli.delaunay.nothing_to_write 2 STDERR "nothing to write"
  COMMAND delaunay ${fixtures}/three_sites.csv)
file(WRITE ${delaunay_out}/exists.geojson "keep me")
geovor_cli_expect(cli.delaunay.refuses_existing 4 STDERR "exists.*--overwrite"
  COMMAND delaunay ${fixtures}/three_sites.csv -o ${delaunay_out}/exists.geojson)
