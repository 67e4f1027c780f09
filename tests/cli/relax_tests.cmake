# CLI tests of `geovor relax` (included by tests/cli/CMakeLists.txt): energy decreasing on stderr,
# outputs read back by GDAL (check_relax.cmake), the same cells as `geovor cells`, the same result
# with every relocation strategy, degenerate inputs, errors.
set(check_relax ${CMAKE_CURRENT_SOURCE_DIR}/check_relax.cmake)
set(relax_out ${CMAKE_CURRENT_BINARY_DIR}/relax)
file(MAKE_DIRECTORY ${relax_out})

# geovor_cli_relax(name input cells iterations output sites [extra args...])
function(geovor_cli_relax name input cells iterations output sites)
  string(REPLACE ";" "|" extra "${ARGN}")
  add_test(NAME cli.relax.${name}
    COMMAND ${CMAKE_COMMAND} -DGEOVOR=$<TARGET_FILE:geovor_cli> -DINPUT=${input} -DOUTPUT=${relax_out}/${output}
            -DSITES=${relax_out}/${sites} -DCELLS=${cells} -DITERATIONS=${iterations} "-DARGS=${extra}"
            -P ${check_relax}
    WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
  set_tests_properties(cli.relax.${name} PROPERTIES LABELS cli)
endfunction()

# 5,631 stations (3 rows merged): 8 iterations, the energy printed must fall at every one.
geovor_cli_relax(weather_geojson ${stations} 5631 8 weather.geojson weather_sites.geojson)
geovor_cli_relax(weather_gpkg ${stations} 5631 4 weather.gpkg weather_sites.fgb --relocation naive)
geovor_cli_relax(weather_rebuild ${stations} 5631 4 weather_rebuild.fgb weather_sites.gpkg --relocation rebuild)
# Degenerate inputs: three sites (lunes), one hemisphere (ghost triangles).
geovor_cli_relax(three_sites ${fixtures}/three_sites.csv 3 3 three.geojson three_sites.geojson)
# Equally spaced sites on the equator are a fixed point (every move 0).
geovor_cli_expect(cli.relax.equator 0 STDERR "\n +3 +[0-9.e+-]+ +0\\.000 +0\\.000 "
  COMMAND relax ${fixtures}/equator.csv -o ${relax_out}/equator.geojson -n 3 --overwrite)
geovor_cli_relax(hemisphere ${fixtures}/hemisphere.csv 20 5 hemisphere.geojson hemisphere_sites.geojson)
# Two sites become antipodal at the first iteration and stay: the energy is flat after it, so only
# the exit code and the outputs are checked.
geovor_cli_expect(cli.relax.two_sites 0 STDERR "final energy 1\\.2566370614359[0-9]*e\\+01"
  COMMAND relax ${fixtures}/two_sites.csv -o ${relax_out}/two.geojson -n 2 --overwrite)
# One site (the whole Earth) has no centroid and stays.
geovor_cli_expect(cli.relax.one_site 0 STDERR "1 site\\(s\\) without a centroid kept in place"
  COMMAND relax ${fixtures}/one_site.csv -o ${relax_out}/one.geojson -n 2 --overwrite)

# No iteration: exactly the file `geovor cells` writes.
geovor_cli_expect(cli.relax.zero_iterations 0
  COMMAND relax ${stations} -o ${relax_out}/zero.geojson -n 0 --overwrite -q)
geovor_cli_expect(cli.relax.cells_reference 0
  COMMAND cells ${stations} -o ${relax_out}/cells_reference.geojson --overwrite -q)
set_tests_properties(cli.relax.zero_iterations PROPERTIES FIXTURES_SETUP relax_zero)
set_tests_properties(cli.relax.cells_reference PROPERTIES FIXTURES_SETUP relax_cells_reference)
add_test(NAME cli.relax.zero_iterations_same_as_cells
  COMMAND ${CMAKE_COMMAND} -E compare_files ${relax_out}/zero.geojson ${relax_out}/cells_reference.geojson)
set_tests_properties(cli.relax.zero_iterations_same_as_cells PROPERTIES LABELS cli
  FIXTURES_REQUIRED "relax_zero;relax_cells_reference")

# geovor_cli_relax_strategies(name input iterations): every relocation strategy gives the same
# cells (cli.relax.<name>_<how>_same_as_filtered) and sites (<name>_sites_...) to the byte.
function(geovor_cli_relax_strategies name input iterations)
  foreach(how filtered naive rebuild)
    geovor_cli_expect(cli.relax.${name}_${how} 0
      COMMAND relax ${input} -o ${relax_out}/${name}_${how}.geojson -n ${iterations} --relocation ${how}
              --sites-output ${relax_out}/${name}_sites_${how}.csv --overwrite -q)
    set_tests_properties(cli.relax.${name}_${how} PROPERTIES FIXTURES_SETUP relax_${name}_${how})
  endforeach()
  foreach(how naive rebuild)
    foreach(what ${name} ${name}_sites)
      set(ext geojson)
      if(what STREQUAL "${name}_sites")
        set(ext csv)
      endif()
      add_test(NAME cli.relax.${what}_${how}_same_as_filtered
        COMMAND ${CMAKE_COMMAND} -E compare_files ${relax_out}/${what}_filtered.${ext} ${relax_out}/${what}_${how}.${ext})
      set_tests_properties(cli.relax.${what}_${how}_same_as_filtered PROPERTIES LABELS cli
        FIXTURES_REQUIRED "relax_${name}_filtered;relax_${name}_${how}")
    endforeach()
  endforeach()
endfunction()

# Every relocation strategy gives the same file, to the byte.
geovor_cli_relax_strategies(strategy ${stations} 5)
# --quiet prints nothing.
geovor_cli_expect(cli.relax.quiet 0 STDERR "^$"
  COMMAND relax ${fixtures}/cube_corners.csv -o ${relax_out}/quiet.geojson -n 2 --overwrite -q)
# --tolerance-m stops once no site moves that far: the cube corners (geodetic latitudes, so not
# quite a cube) move 20 km at the first iteration, below 100 km.
geovor_cli_expect(cli.relax.tolerance 0 STDERR "\n +1 [^\n]*\nfinal energy"
  COMMAND relax ${fixtures}/cube_corners.csv -o ${relax_out}/tolerance.geojson -n 50 --tolerance-m 100000 --overwrite)

# Errors: usage (exit 2), an existing output refused before any work (exit 4), a missing input (4).
geovor_cli_expect(cli.relax.bad_relocation 2 STDERR "--relocation: expected filtered, naive or rebuild"
  COMMAND relax ${stations} -o ${relax_out}/bad.geojson --relocation fast)
geovor_cli_expect(cli.relax.negative_iterations 2
  COMMAND relax ${stations} -o ${relax_out}/bad.geojson -n -1)
geovor_cli_expect(cli.relax.without_output 2 COMMAND relax ${stations})
file(WRITE ${relax_out}/exists.geojson "keep me")
geovor_cli_expect(cli.relax.refuses_existing 4 STDERR "exists.*--overwrite"
  COMMAND relax ${fixtures}/three_sites.csv -o ${relax_out}/exists.geojson)
geovor_cli_expect(cli.relax.refuses_existing_sites 4 STDERR "exists.*--overwrite"
  COMMAND relax ${fixtures}/three_sites.csv -o ${relax_out}/new.geojson --sites-output ${relax_out}/exists.geojson)
geovor_cli_expect(cli.relax.missing_input 4 STDERR "no_such_file\\.csv"
  COMMAND relax ${relax_out}/no_such_file.csv -o ${relax_out}/missing.geojson)
geovor_cli_expect(cli.help.relax 0 STDOUT "--iterations.*Examples:" COMMAND relax --help)

# A 31x31 grid at 0.001 degree (every four neighbours co-circular): the relocation strategies
# number the triangles differently, and collapsed Voronoi vertices took the position of the
# smallest triangle id, so the cells differed in the 7th decimal (issue 14).
geovor_cli_relax_strategies(grid ${fixtures}/grid31_sydney.csv 3)
