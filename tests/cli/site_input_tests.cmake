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

# ------------------------------------------------------------------------------------------------
# How a site table is read (issue 16, the input side): the files are written here, the expected
# counts and values worked out by hand from them (GDAL's gdaltransform for --s-srs).
set(si ${site_input_out})
# Column names of public data sets: GTFS stops.txt, GBIF occurrences (tab-separated, no
# extension), a European spreadsheet (semicolons, decimal commas, "Latitude (deg)").
file(WRITE ${si}/stops.txt "stop_id,stop_name,stop_lat,stop_lon\nS1,Gare,48.8443,2.3744\nS2,Opera,48.8719,2.3316\n")
geovor_cli_expect(cli.site_input.gtfs_stops 0 STDOUT "\nrows: 2\nsites: 2\nmerged: 0\nrejected: 0\n" COMMAND info ${si}/stops.txt)
file(WRITE ${si}/gbif_occurrences "gbifID\tspecies\tdecimalLatitude\tdecimalLongitude\n1\tParus major\t52.1\t5.2\n2\tParus major\t-33.9\t18.4\n3\tParus major\t\t\n")
geovor_cli_expect(cli.site_input.gbif_tab_no_extension 0 STDOUT "\nrows: 3\nsites: 2\nmerged: 0\nrejected: 1\n"
  STDERR "gbif_occurrences: row 3 \\(line 4\\) rejected: decimalLatitude: empty value" COMMAND info ${si}/gbif_occurrences)
file(WRITE ${si}/europe.csv "Name;Latitude (deg);Longitude (deg);Einwohner\nParis;48,8566;2,3522;2100000\nBerlin;52,52;13,405;3700000\n")
# The decimal commas are read (Berlin's latitude is 52.52, so the cell of (52.5, 13.4) is Berlin's)
# and the fields are kept as written.
file(WRITE ${si}/berlin_query.csv "id,lat,lon\nq,52.52,13.405\n")
geovor_cli_expect(cli.site_input.semicolon_decimal_comma 0 STDOUT "^query_id,site_index,site_id,distance_m,id,lat,lon\nq,1,Berlin,0,q,52.52,13.405\n$"
  COMMAND nearest --sites ${si}/europe.csv --queries ${si}/berlin_query.csv)
geovor_cli_expect(cli.site_input.semicolon_fields_kept 0 STDOUT "\"Latitude \\(deg\\)\":\"48,8566\""
  COMMAND cells ${si}/europe.csv -o - -q)
# Several equally good columns: refused with the candidates (NYC taxi trips).
file(WRITE ${si}/taxi.csv "pickup_longitude,pickup_latitude,dropoff_longitude,dropoff_latitude\n-73.98,40.75,-73.95,40.78\n")
geovor_cli_expect(cli.site_input.ambiguous_columns 3
  STDERR "taxi\\.csv: ambiguous latitude column: 'pickup_latitude', 'dropoff_latitude' are equally likely; choose one with --lat-field"
  COMMAND info ${si}/taxi.csv)
geovor_cli_expect(cli.site_input.ambiguous_columns_named 0 STDOUT "\nsites: 1\n"
  COMMAND info ${si}/taxi.csv --lat-field dropoff_latitude --lon-field dropoff_longitude)

# Encodings: ISO-8859-1 text rejects its row without --encoding and is read with it.
string(ASCII 252 u_umlaut_latin1)
file(WRITE ${si}/latin1.csv "id,name,lat,lon\nZRH,Z${u_umlaut_latin1}rich,47.37,8.54\nGVA,Geneve,46.2,6.14\n")
geovor_cli_expect(cli.site_input.invalid_utf8_row 0 STDOUT "\nrows: 2\nsites: 1\nmerged: 0\nrejected: 1\n"
  STDERR "latin1\\.csv: row 1 \\(line 2\\) rejected: name: not valid UTF-8 \\(byte 0xFC at byte 2 of the field\\); give the file's encoding, e\\.g\\. --encoding ISO-8859-1"
  COMMAND info ${si}/latin1.csv)
geovor_cli_expect(cli.site_input.encoding_latin1 0 STDOUT "\"name\":\"Zürich\""
  COMMAND cells ${si}/latin1.csv -o - -q --encoding ISO-8859-1)
geovor_cli_expect(cli.site_input.encoding_unknown 2 STDERR "--encoding NOPE-1: not an encoding iconv knows"
  COMMAND info ${si}/latin1.csv --encoding NOPE-1)

# Header problems are bad data (exit 3, the file and the column) in every command.
file(WRITE ${si}/lat_twice.csv "id,lat,lon,lat\nA,1,2,3\nB,4,5,6\nC,-7,8,9\n")
set(twice "lat_twice\\.csv: header: column 4 'lat' has the same name as column 2 'lat'; rename one of them")
geovor_cli_expect(cli.site_input.lat_twice_info 3 STDERR "${twice}" COMMAND info ${si}/lat_twice.csv)
geovor_cli_expect(cli.site_input.lat_twice_cells 3 STDERR "${twice}" COMMAND cells ${si}/lat_twice.csv -o ${si}/never.geojson)
geovor_cli_expect(cli.site_input.lat_twice_delaunay 3 STDERR "${twice}" COMMAND delaunay ${si}/lat_twice.csv -o ${si}/never.geojson)
geovor_cli_expect(cli.site_input.lat_twice_relax 3 STDERR "${twice}" COMMAND relax ${si}/lat_twice.csv -o ${si}/never.geojson)
geovor_cli_expect(cli.site_input.lat_twice_index 3 STDERR "${twice}" COMMAND index ${si}/lat_twice.csv -o ${si}/never.gvi)
geovor_cli_expect(cli.site_input.lat_twice_nearest 3 STDERR "${twice}"
  COMMAND nearest --sites ${si}/lat_twice.csv --queries ${si}/berlin_query.csv)
file(WRITE ${si}/unnamed_column.csv "id,,lat,lon\nA,x,1,2\n")
geovor_cli_expect(cli.site_input.unnamed_column 3 STDERR "unnamed_column\\.csv: header: column 2 has no name"
  COMMAND cells ${si}/unnamed_column.csv -o ${si}/never.geojson)
# A trailing comma from a spreadsheet: an unnamed last column, dropped while every row leaves it empty.
file(WRITE ${si}/trailing_comma.csv "id,lat,lon,\nA,1,2,\nB,3,4,\n")
geovor_cli_expect(cli.site_input.trailing_comma 0 STDOUT "\"id\":\"B\",\"lat\":3,\"lon\":4}"
  COMMAND cells ${si}/trailing_comma.csv -o - -q)
file(WRITE ${si}/trailing_value.csv "id,lat,lon,\nA,1,2,\nB,3,4,lost\n")
geovor_cli_expect(cli.site_input.trailing_value 3
  STDERR "trailing_value\\.csv: header: column 4 has no name, but row 2 \\(line 3\\) has a value there: 'lost'; name the column"
  COMMAND info ${si}/trailing_value.csv)
add_test(NAME cli.site_input.nothing_written COMMAND ${CMAKE_COMMAND} -E cat ${si}/never.geojson)
set_tests_properties(cli.site_input.nothing_written PROPERTIES LABELS cli WILL_FAIL ON
  DEPENDS "cli.site_input.lat_twice_cells;cli.site_input.lat_twice_delaunay;cli.site_input.lat_twice_relax;cli.site_input.unnamed_column;cli.site_input.dms_cells")

# No site left: exit 3 with the reason, in every command, and no output.
file(WRITE ${si}/dms.csv "name,lat,lon\nPittsburgh,\"40°26'46\"\"N\",\"79°58'56\"\"W\"\n")
set(dms "dms\\.csv: no usable site \\(1 rows, 1 rejected\\): every row was rejected, the first \\(row 1\\) for lat: '40°26'46\"N' is in degrees, minutes and seconds; geovor reads decimal degrees")
geovor_cli_expect(cli.site_input.dms_info 3 STDERR "${dms}" COMMAND info ${si}/dms.csv)
geovor_cli_expect(cli.site_input.dms_cells 3 STDERR "${dms}" COMMAND cells ${si}/dms.csv -o ${si}/never.geojson)
geovor_cli_expect(cli.site_input.dms_delaunay 3 STDERR "${dms}" COMMAND delaunay ${si}/dms.csv --edges ${si}/never.geojson)
geovor_cli_expect(cli.site_input.dms_relax 3 STDERR "${dms}" COMMAND relax ${si}/dms.csv -o ${si}/never.geojson)
geovor_cli_expect(cli.site_input.dms_index 3 STDERR "${dms}" COMMAND index ${si}/dms.csv -o ${si}/never.gvi)
file(WRITE ${si}/metres.csv "id,lat,lon\nA,6862035,652469\n")
geovor_cli_expect(cli.site_input.metres_hint 3 STDERR "latitude 6862035 is beyond \\+-90; projected coordinates \\(metres\\)\\? give their CRS with --s-srs"
  COMMAND info ${si}/metres.csv)
geovor_cli_expect(cli.site_input.polygon_layer_cells 3 STDERR "polygons_only\\.geojson: no usable site \\(2 rows, 2 rejected\\)"
  COMMAND cells tests/cli/fixtures/polygons_only.geojson -o ${si}/never.gpkg)

# --s-srs: x/y in Lambert-93 (EPSG:2154); Paris at (652469, 6862035) is lon 2.3521997195163,
# lat 48.8565976653841 for gdaltransform -s_srs EPSG:2154 -t_srs EPSG:4326; a row far outside the
# CRS's area of use is rejected.
file(WRITE ${si}/lambert93.csv "name;X;Y\nParis;652469;6862035\nMars;1e12;0\n")
file(WRITE ${si}/paris_query.csv "id,lat,lon\nq,48.8565976653841,2.3521997195163\n")
geovor_cli_expect(cli.site_input.s_srs 0 STDOUT "^query_id,site_index,site_id,distance_m,id,lat,lon\nq,0,Paris,(0|[0-9.]+e-[0-9]+|0\\.00[0-9]*),q,"
  STDERR "lambert93\\.csv: row 2 \\(line 3\\) rejected: X, Y: point \\(1e\\+12, 0\\) is far outside RGF93 v1 / Lambert-93 \\(EPSG:2154\\)"
  COMMAND nearest --sites ${si}/lambert93.csv --s-srs EPSG:2154 --queries ${si}/paris_query.csv)
# A GeoJSON in Web Mercator with a corrupt point at (1e25, 1e25): rejected at once instead of
# stalling PROJ (1e18 took 19 s); a point beyond x = 20037508.34 m is another turn of the Earth.
file(WRITE ${si}/mercator.geojson "{\"type\":\"FeatureCollection\",\"crs\":{\"type\":\"name\",\"properties\":{\"name\":\"urn:ogc:def:crs:EPSG::3857\"}},\"features\":[
{\"type\":\"Feature\",\"properties\":{\"id\":\"huge\"},\"geometry\":{\"type\":\"Point\",\"coordinates\":[1e25,1e25]}},
{\"type\":\"Feature\",\"properties\":{\"id\":\"wrapped\"},\"geometry\":{\"type\":\"Point\",\"coordinates\":[30000000,0]}},
{\"type\":\"Feature\",\"properties\":{\"id\":\"a\"},\"geometry\":{\"type\":\"Point\",\"coordinates\":[0,0]}},
{\"type\":\"Feature\",\"properties\":{\"id\":\"b\"},\"geometry\":{\"type\":\"Point\",\"coordinates\":[1000000,1000000]}}]}\n")
geovor_cli_expect(cli.site_input.mercator_far_points 0 STDOUT "\nrows: 4\nsites: 2\nmerged: 0\nrejected: 2\n"
  STDERR "mercator\\.geojson: row 1 rejected: feature 1 \\(FID 0\\): point \\(1e\\+25, 1e\\+25\\) is far outside WGS 84 / Pseudo-Mercator \\(EPSG:3857\\)[^\n]*\n[^\n]*row 2 rejected: feature 2 \\(FID 1\\): point \\(30000000, 0\\) is outside the area of use"
  COMMAND info ${si}/mercator.geojson)
set_tests_properties(cli.site_input.mercator_far_points PROPERTIES TIMEOUT 30)

# Ids that repeat: a warning with the count and examples; --id-field '#row' makes ids row numbers.
file(WRITE ${si}/repeated_names.csv "name,lat,lon\nSan Jose,37.34,-121.89\nSan Jose,9.93,-84.08\nParis,48.86,2.35\nSan Jose,10.1,-84.2\nParis,33.66,-95.56\n")
geovor_cli_expect(cli.site_input.duplicate_ids_warned 0
  STDERR "repeated_names\\.csv: warning: 3 rows have the id of an earlier row \\(id column 'name'; e\\.g\\. 'San Jose' rows 1 2 4; 'Paris' rows 3 5\\); --id-field '#row' makes the row number the id"
  COMMAND cells ${si}/repeated_names.csv -o - -q)
# Feature ids stay unique: with repeated ids, the feature id is the site index.
geovor_cli_expect(cli.site_input.duplicate_ids_feature_ids 0
  STDOUT "{\"type\":\"Feature\",\"id\":0,[^\n]*\"site_id\":\"San Jose\"[^\n]*\n{\"type\":\"Feature\",\"id\":1,[^\n]*\"site_id\":\"San Jose\""
  COMMAND cells ${si}/repeated_names.csv -o - -q)
geovor_cli_expect(cli.site_input.row_number_ids 0
  STDOUT "\"id\":\"1\",[^\n]*\"site_id\":\"1\",[^\n]*\"name\":\"San Jose\"[^\n]*\n[^\n]*\"id\":\"2\",[^\n]*\"name\":\"San Jose\""
  COMMAND cells ${si}/repeated_names.csv -o - -q --id-field "#row")
geovor_cli_expect(cli.site_input.row_number_ids_no_warning 0 STDERR "^$"
  COMMAND info ${si}/repeated_names.csv --id-field "#row")

# A NUL and a line break in a rejected field: escaped in the message and in the --report, which
# keeps one line per row.
geovor_cli_expect(cli.site_input.nul_in_report 0
  STDOUT "^row,line,id,status,site_index,detail\n2,4,\"b\",site,0,\n1,2,,rejected,,\"lat: '1\\\\0x\\\\ny' is not a number\"\n$"
  STDERR "nul\\.csv: row 1 \\(line 2\\) rejected: lat: '1\\\\0x\\\\ny' is not a number\n"
  SCRIPT "printf 'id,lat,lon\\na,\"1\\000x\\ny\",2\\nb,3,4\\n' > ${si}/nul.csv && \"$0\" cells ${si}/nul.csv -o ${si}/nul.geojson --overwrite -q --report ${si}/nul_report.csv && cat ${si}/nul_report.csv")
