# CLI tests of the site options shared by every subcommand (tools/site_input.cpp): --layer picks
# one layer of a multi-layer OGR source; without it such a source is a usage error naming the
# layers and the option; --layer on a CSV file is a usage error. Included by tests/cli/CMakeLists.txt.
set(site_input_out ${CMAKE_CURRENT_BINARY_DIR}/site_input)
file(MAKE_DIRECTORY ${site_input_out})
set(two_layers ${site_input_out}/two_layers.gpkg)
# A GeoPackage with the point layers "three" (3 sites) and "two" (2 sites), made by ogr2ogr.
add_test(NAME cli.site_input.make_two_layers
  COMMAND sh -c "rm -f \"$0\" && ogr2ogr -f GPKG \"$0\" datasets/fixtures/three_sites.csv -nln three -oo X_POSSIBLE_NAMES=lon_deg -oo Y_POSSIBLE_NAMES=lat_deg && ogr2ogr -update -f GPKG \"$0\" datasets/fixtures/two_sites.csv -nln two -oo X_POSSIBLE_NAMES=lon_deg -oo Y_POSSIBLE_NAMES=lat_deg"
          ${two_layers}
  WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
set_tests_properties(cli.site_input.make_two_layers PROPERTIES LABELS cli FIXTURES_SETUP two_layers)
geovor_cli_expect(cli.site_input.layer_two 0 STDOUT "rows: 2\nsites: 2\n" COMMAND info ${two_layers} --layer two)
geovor_cli_expect(cli.site_input.layer_three 0 STDOUT "rows: 3\nsites: 3\n" COMMAND info ${two_layers} --layer three)
geovor_cli_expect(cli.site_input.layer_missing 2 STDERR "2 layers; choose one of them \\(--layer NAME\\)"
  COMMAND info ${two_layers})
geovor_cli_expect(cli.site_input.layer_unknown 2 STDERR "four" COMMAND info ${two_layers} --layer four)
set_tests_properties(cli.site_input.layer_two cli.site_input.layer_three cli.site_input.layer_missing
  cli.site_input.layer_unknown PROPERTIES FIXTURES_REQUIRED two_layers)
geovor_cli_expect(cli.site_input.layer_on_csv 2 STDERR "--layer is for OGR sources"
  COMMAND info datasets/fixtures/three_sites.csv --layer x)
