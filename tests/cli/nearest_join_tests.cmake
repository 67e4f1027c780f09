# geovor nearest as a spatial join: named query columns, query attributes passed through, site
# fields joined from the sites, --max-distance-m, OGR query layers and OGR output read back by
# GDAL (ogrinfo, ogr2ogr), -q. Expected values are those worked out for cli.nearest.* in
# CMakeLists.txt (AGGH is site 0 at distance 0 from its own position; the North Pole's nearest
# station is CYLT, site 407, 837653.78 m away) and the stations' names from
# datasets/weather_stations.csv (AGGH: "Honiara / Henderson, Solomon Islands"; CYLT: "Alert
# Airport, Canada"; CWCF: "Berens River Cs , Man., Canada").
set(join_dir ${CMAKE_CURRENT_BINARY_DIR}/nearest_join)
file(MAKE_DIRECTORY ${join_dir})
# Lines: 1 header, 2 AGGH, 3 North Pole, 4 a malformed latitude, 5 too few fields, 6 CYBV (merged
# into CWCF's site).
file(WRITE ${join_dir}/trips.csv
  "trip_id,pickup_latitude,pickup_longitude,fare\n"
  "t1,-9.4166645,160.0500018,12.50\n"
  "t2,90,0,3.00\n"
  "t3,north,0,7.25\n"
  "t4,1\n"
  "t5,52.3500021,-97.0333361,1.00\n")
set(join_args --sites ${stations} --queries ${join_dir}/trips.csv
    --query-lat-field pickup_latitude --query-lon-field pickup_longitude --query-id-field trip_id)

# Named columns; every query column passed through as written; a malformed query keeps its row
# (an empty match, its fields when it has the header's four, else none) and is reported.
geovor_cli_expect(cli.nearest_join.named_columns 0
  STDOUT "^query_id,site_index,site_id,distance_m,trip_id,pickup_latitude,pickup_longitude,fare\nt1,0,AGGH,0,t1,-9\\.4166645,160\\.0500018,12\\.50\nt2,407,CYLT,837653\\.78[0-9]*,t2,90,0,3\\.00\nt3,,,,t3,north,0,7\\.25\n5,,,,,,,\nt5,54,CWCF,0,t5,52\\.3500021,-97\\.0333361,1\\.00\n$"
  STDERR "trips\\.csv: line 4: pickup_latitude: 'north' is not a number\n.*trips\\.csv: line 5: expected 4 fields, found 2\n"
  COMMAND nearest ${join_args})
# A named column that is not in the header: a usage error naming it and the columns.
geovor_cli_expect(cli.nearest_join.unknown_query_column 2
  STDERR "trips\\.csv: --query-lat-field 'dropoff_latitude' is not a column of the header \\(trip_id, pickup_latitude, pickup_longitude, fare\\)"
  COMMAND nearest --sites ${stations} --queries ${join_dir}/trips.csv --query-lat-field dropoff_latitude)
# Site attributes joined (the site's first row's: t5 gets CWCF's name, not CYBV's), quoted as CSV.
geovor_cli_expect(cli.nearest_join.site_fields 0
  STDOUT "\nt1,0,AGGH,0,t1,-9\\.4166645,160\\.0500018,12\\.50,\"Honiara / Henderson, Solomon Islands\",-9\\.4166645\nt2,407,CYLT,[0-9.]+,t2,90,0,3\\.00,\"Alert Airport, Canada\",82\\.5166655\nt3,,,,t3,north,0,7\\.25,,\n5,,,,,,,,,\nt5,54,CWCF,0,t5,52\\.3500021,-97\\.0333361,1\\.00,\"Berens River Cs , Man\\., Canada\",52\\.3500021\n$"
  COMMAND nearest ${join_args} --site-fields name,lat_deg)
geovor_cli_expect(cli.nearest_join.unknown_site_field 2 STDERR "site field 'elevation' is not a column of the sites"
  COMMAND nearest ${join_args} --site-fields name,elevation)
# --max-distance-m: CYLT is 837653.78 m from the pole, so 837000 leaves t2 without a match (one
# row, empty match) and 837700 keeps it.
geovor_cli_expect(cli.nearest_join.max_distance_empty_match 0
  STDOUT "\nt1,0,AGGH,0,[^\n]*\nt2,,,,t2,90,0,3\\.00\nt3,"
  STDERR "2 malformed"
  COMMAND nearest ${join_args} --max-distance-m 837000)
geovor_cli_expect(cli.nearest_join.max_distance_match 0 STDOUT "\nt2,407,CYLT,837653\\.78"
  COMMAND nearest ${join_args} --max-distance-m 837700)
geovor_cli_expect(cli.nearest_join.max_distance_negative 2 STDERR "--max-distance-m"
  COMMAND nearest ${join_args} --max-distance-m -1)

# GeoPackage output: points with typed attributes, read back by GDAL; the malformed queries are
# features with a null geometry (line 5 has no trip_id: its query_id is its line number).
# (Scripts holding semicolons are written to files: a CMake list would split them.)
string(REPLACE ";" " " join_args_text "${join_args}")
file(WRITE ${join_dir}/gpkg.sh "set -e
\"$1\" nearest ${join_args_text} --site-fields name -o ${join_dir}/trips.gpkg --overwrite 2>/dev/null
ogrinfo -ro -so -al ${join_dir}/trips.gpkg | grep -E '^(Layer name|Geometry|Feature Count|[a-z_]+):'
ogrinfo -ro -q -al ${join_dir}/trips.gpkg -fid 1
printf 'null: %s\\n' $(ogrinfo -ro -q ${join_dir}/trips.gpkg -sql 'SELECT query_id FROM nearest WHERE geom IS NULL' | sed -n 's/ *query_id (String) = //p' | paste -sd, -)
")
geovor_cli_expect(cli.nearest_join.gpkg 0
  STDOUT "Layer name: nearest\nGeometry: Point\nFeature Count: 5\n.*query_id: String.*site_index: Integer64.*site_id: String.*distance_m: Real.*trip_id: String.*fare: String.*name: String.*OGRFeature\\(nearest\\):1\n  query_id \\(String\\) = t1\n  site_index \\(Integer64\\) = 0\n  site_id \\(String\\) = AGGH\n  distance_m \\(Real\\) = 0\n.*  name \\(String\\) = Honiara / Henderson, Solomon Islands\n  POINT \\(160\\.0500018 -9\\.4166645\\).*null: t3,5\n$"
  SCRIPT "sh ${join_dir}/gpkg.sh \"$0\"")
# --format names the driver whatever the extension; a format other than CSV cannot go to stdout.
geovor_cli_expect(cli.nearest_join.format_flatgeobuf_refuses_null_point 3 STDERR "trips\\.bin: feature 3 has a null point \\(a row without a position\\), which FlatGeobuf cannot hold"
  COMMAND nearest ${join_args} -f FlatGeobuf -o ${join_dir}/trips.bin --overwrite)
geovor_cli_expect(cli.nearest_join.format_to_stdout 2 STDERR "cannot be written to standard output"
  COMMAND nearest ${join_args} -f GPKG)
geovor_cli_expect(cli.nearest_join.geojson_to_stdout 0
  STDOUT "^\\{\"type\":\"FeatureCollection\",\"name\":\"nearest\".*\"query_id\":\"t1\",\"site_index\":0,\"site_id\":\"AGGH\""
  COMMAND nearest ${join_args} -f GeoJSON)
# An extension no OGR driver knows is refused, not written as CSV.
geovor_cli_expect(cli.nearest_join.unknown_extension 2 STDERR "trips\\.unknownext"
  COMMAND nearest ${join_args} -o ${join_dir}/trips.unknownext --overwrite)

# An OGR query layer, one of two in a GeoPackage (--layer), written by ogr2ogr: the same matches,
# every attribute kept, the query_id its id column.
geovor_cli_expect(cli.nearest_join.ogr_layer 0
  STDOUT "^query_id,site_index,site_id,distance_m,trip_id,fare,name\nt1,0,AGGH,0,t1,12\\.5,\"Honiara / Henderson, Solomon Islands\"\nt2,407,CYLT,837653\\.78[0-9]*,t2,3,\"Alert Airport, Canada\"\n$"
  SCRIPT "rm -f ${join_dir}/q.gpkg && printf 'trip_id,lat,lon,fare\\nt1,-9.4166645,160.0500018,12.5\\nt2,90,0,3\\n' > ${join_dir}/q.csv && printf 'id,lat,lon\\nx,0,0\\n' > ${join_dir}/other.csv && ogr2ogr -f GPKG ${join_dir}/q.gpkg ${join_dir}/q.csv -nln trips -oo X_POSSIBLE_NAMES=lon -oo Y_POSSIBLE_NAMES=lat -oo AUTODETECT_TYPE=YES -select trip_id,fare && ogr2ogr -update ${join_dir}/q.gpkg ${join_dir}/other.csv -nln other -oo X_POSSIBLE_NAMES=lon -oo Y_POSSIBLE_NAMES=lat && \"$0\" nearest --sites ${stations} --queries ${join_dir}/q.gpkg --layer trips --query-id-field trip_id --site-fields name")
geovor_cli_expect(cli.nearest_join.layer_for_csv 2 STDERR "--layer is for OGR query sources"
  COMMAND nearest ${join_args} --layer trips)

# Exactness: the site_index, site_id and distance_m of 3000 queries are the same through the
# GeoPackage (read back by ogr2ogr, distances printed with 17 digits) as in the CSV stream (which
# the unit tests check against brute force); compared as doubles by awk.
file(WRITE ${join_dir}/same.sh "set -e
cd ${join_dir}
awk 'BEGIN { print \"id,lat,lon\"; for (i = 0; i < 3000; i++) printf \"q%d,%.6f,%.6f\\n\", i, (i * 7.123) % 178 - 89, (i * 13.77) % 360 - 180 }' > grid.csv
\"$1\" nearest --sites ${PROJECT_SOURCE_DIR}/${stations} --queries grid.csv -o grid_out.csv --overwrite -q
\"$1\" nearest --sites ${PROJECT_SOURCE_DIR}/${stations} --queries grid.csv -o grid_out.gpkg --overwrite -q
ogr2ogr -f CSV /vsistdout/ grid_out.gpkg -dialect SQLite -sql \"SELECT query_id, site_index, site_id, printf('%!.17g', distance_m) AS d FROM nearest\" | tail -n +2 | tr -d '\"' > gdal.csv
tail -n +2 grid_out.csv | cut -d, -f1-4 | paste -d, - gdal.csv | awk -F, '$1 == $5 && $2 == $6 && $3 == $7 && $4 + 0 == $8 + 0 { same++ } END { print same \" same\" }'
")
geovor_cli_expect(cli.nearest_join.gpkg_same_as_csv 0 STDOUT "^3000 same\n$" SCRIPT "sh ${join_dir}/same.sh \"$0\"")

# -q: the merged sites of a site table are not listed (three stations share another's position).
geovor_cli_expect(cli.nearest_join.quiet 0 STDOUT "^rc=0 merged=0\n$"
  SCRIPT "\"$0\" nearest --sites ${stations} --queries ${nearest_dir}/headerless.csv -q > /dev/null 2> ${join_dir}/quiet.err || echo failed && echo rc=0 merged=$(grep -c merged ${join_dir}/quiet.err)")
# GeoJSON, written by geovor itself: a malformed query's feature has a null geometry, which GDAL
# reads back as such (ogrinfo prints no geometry line for it; the answered ones are points).
file(WRITE ${join_dir}/geojson.sh "set -e
\"$1\" nearest ${join_args_text} -o ${join_dir}/trips.geojson --overwrite 2>/dev/null
ogrinfo -ro -q ${join_dir}/trips.geojson -sql 'SELECT query_id FROM nearest WHERE OGR_GEOMETRY IS NULL' | sed -n 's/ *query_id (String) = //p' | paste -sd, -
ogrinfo -ro -q ${join_dir}/trips.geojson -sql 'SELECT query_id FROM nearest WHERE OGR_GEOMETRY IS NOT NULL' | sed -n 's/ *query_id (String) = //p' | paste -sd, -
")
geovor_cli_expect(cli.nearest_join.geojson_null_points 0 STDOUT "^t3,5\nt1,t2,t5\n$" SCRIPT "sh ${join_dir}/geojson.sh \"$0\"")

# Query columns found by name as the sites' are: pickup_latitude alone is the latitude (before,
# only lat, latitude, lat_deg and y were looked for: "no latitude/longitude columns"); pickup and
# dropoff together are ambiguous, and a name twice is a header error, both exit 3 naming them.
geovor_cli_expect(cli.nearest_join.detected_query_columns 0
  STDOUT "^query_id,site_index,site_id,distance_m,trip_id,pickup_latitude,pickup_longitude,fare\nt1,0,AGGH,0,"
  COMMAND nearest --sites ${stations} --queries ${join_dir}/trips.csv --query-id-field trip_id -q)
file(WRITE ${join_dir}/two_trips.csv "pickup_latitude,pickup_longitude,dropoff_latitude,dropoff_longitude\n1,2,3,4\n")
geovor_cli_expect(cli.nearest_join.ambiguous_query_columns 3
  STDERR "two_trips\\.csv: ambiguous latitude column: 'pickup_latitude', 'dropoff_latitude' are equally likely; choose one with --query-lat-field"
  COMMAND nearest --sites ${stations} --queries ${join_dir}/two_trips.csv)
file(WRITE ${join_dir}/twice.csv "stop_id,stop_lat,stop_lon,stop_lat\ns,1,2,3\n")
geovor_cli_expect(cli.nearest_join.query_name_twice 3
  STDERR "twice\\.csv: header: column 4 'stop_lat' has the same name as column 2 'stop_lat'"
  COMMAND nearest --sites ${stations} --queries ${join_dir}/twice.csv)
# An OGR query layer's field types carry over to point output (before: every query column String),
# read back by ogrinfo: Integer, Real and Date stay so, an empty Integer is null.
geovor_cli_expect(cli.nearest_join.query_types_kept 0
  STDOUT "trip: String.*pop: Integer .*elev: Real.*when: Date.*site_id \\(String\\) = LFPO.*pop \\(Integer\\) = 2100000\n  elev \\(Real\\) = 35\\.5\n  when \\(Date\\) = 2024/05/01.*site_id \\(String\\) = AGGH.*pop \\(Integer\\) = \\(null\\)\n  elev \\(Real\\) = 8\\.25"
  SCRIPT "rm -f ${join_dir}/typed.gpkg ${join_dir}/typed_out.gpkg && printf 'trip,lat,lon,pop,elev,when\\nt1,48.85,2.35,2100000,35.5,2024-05-01\\nt2,-9.4166645,160.0500018,,8.25,2023-01-02\\n' > ${join_dir}/typed.csv && ogr2ogr -f GPKG ${join_dir}/typed.gpkg ${join_dir}/typed.csv -nln q -oo X_POSSIBLE_NAMES=lon -oo Y_POSSIBLE_NAMES=lat -oo AUTODETECT_TYPE=YES && \"$0\" nearest --sites ${stations} --queries ${join_dir}/typed.gpkg -o ${join_dir}/typed_out.gpkg -q && ogrinfo -ro -so ${join_dir}/typed_out.gpkg nearest && ogrinfo -ro -q ${join_dir}/typed_out.gpkg nearest")

# ogr2ogr's output model on the join too: --nln names the layer, --update adds one to an existing
# GeoPackage (the first kept), read back by ogrinfo.
string(JOIN " " join_args_sh ${join_args})
geovor_cli_expect(cli.nearest_join.nln_and_update 0 STDOUT "1: first \\(Point\\)\n2: second \\(Point\\)" SCRIPT
  "rm -f ${join_dir}/layers.gpkg && \"$0\" nearest ${join_args_sh} -o ${join_dir}/layers.gpkg --nln first -q && \"$0\" nearest ${join_args_sh} -o ${join_dir}/layers.gpkg --nln second --update -q && ogrinfo -ro -q ${join_dir}/layers.gpkg")
# geovor writes its CSV itself: GDAL's creation options do not apply (exit 2, nothing written).
geovor_cli_expect(cli.nearest_join.csv_lco_refused 2 STDERR "--nln, --update, --lco and --dsco apply to OGR point outputs" SCRIPT
  "rm -f ${join_dir}/lco.csv && \"$0\" nearest ${join_args_sh} -o ${join_dir}/lco.csv --lco X=Y -q; rc=$?; test ! -e ${join_dir}/lco.csv || exit 99; exit $rc")
# GPX points with geovor's fields as <extensions> (--dsco), read back: every value in its field.
# A column named as one of GPX's own elements (name, ele, ...) is refused: GDAL's GPX writer
# mixes it up with that element (a `name` column's value was written as `lon`).
file(WRITE ${join_dir}/gpx_queries.csv "lat,lon,label\n1,2,a\n")
file(WRITE ${join_dir}/gpx_named.csv "lat,lon,name\n1,2,a\n")
geovor_cli_expect(cli.nearest_join.gpx_with_extensions 0 STDOUT "ogr_lat \\(Integer\\) = 1\n  ogr_lon \\(Integer\\) = 2\n  ogr_label \\(String\\) = a" SCRIPT
  "rm -f ${join_dir}/q.gpx && \"$0\" nearest --sites ${stations} --queries ${join_dir}/gpx_queries.csv -o ${join_dir}/q.gpx --dsco GPX_USE_EXTENSIONS=YES -q && ogrinfo -ro -q ${join_dir}/q.gpx waypoints")
geovor_cli_expect(cli.nearest_join.gpx_own_element_refused 2 STDERR "field 'name' has the name of one of GPX's own elements" SCRIPT
  "rm -f ${join_dir}/named.gpx && \"$0\" nearest --sites ${stations} --queries ${join_dir}/gpx_named.csv -o ${join_dir}/named.gpx --dsco GPX_USE_EXTENSIONS=YES -q; rc=$?; test ! -e ${join_dir}/named.gpx || exit 99; exit $rc")
