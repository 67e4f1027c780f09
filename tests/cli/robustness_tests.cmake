# Robustness of the `geovor` command under hostile input and faults (issue 5; the matrix in
# docs/robustness.md names these tests). Included by tests/cli/CMakeLists.txt after its helpers
# (geovor_cli_expect, expect_exit.cmake). Every test checks the exit code (0 ok, 2 usage, 3 bad
# data, 4 I/O), that the message names the file, the row or line and the reason, and what was
# written; cli.rows.* check the row accounting of every fixture (check_accounting.cmake).
set(robust_fixtures tests/cli/fixtures)
set(robust_out ${CMAKE_CURRENT_BINARY_DIR}/robustness)
set(big ${robust_out}/big)
file(MAKE_DIRECTORY ${robust_out})
set(stations datasets/weather_stations.csv)
set(check_accounting ${CMAKE_CURRENT_SOURCE_DIR}/check_accounting.cmake)
set(full_disk ${CMAKE_CURRENT_SOURCE_DIR}/full_disk.cmake)

# The fixtures too big to check in, written once by a setup test.
add_test(NAME cli.robust.make_big_fixtures
  COMMAND ${CMAKE_COMMAND} -DDIR=${big} -P ${CMAKE_CURRENT_SOURCE_DIR}/make_big_fixtures.cmake)
set_tests_properties(cli.robust.make_big_fixtures PROPERTIES LABELS cli FIXTURES_SETUP robust_big)
function(robust_needs_big)
  set_tests_properties(${ARGN} PROPERTIES FIXTURES_REQUIRED robust_big)
endfunction()

# ------------------------------------------------------------------------------------------------
# Row accounting: geovor_cli_rows(name file rows sites merged rejected [args...]): info's counts,
# the cells written and the --report lines agree with the hand-worked counts, and
# rows = sites + merged + rejected (test cli.rows.<name>). Row numbers are checked one by one
# except for the 10^6-row file.
function(geovor_cli_rows name file rows sites merged rejected)
  list(JOIN ARGN "|" extra)
  set(each ON)
  if(rows GREATER 100000)
    set(each OFF)
  endif()
  add_test(NAME cli.rows.${name}
    COMMAND ${CMAKE_COMMAND} -DGEOVOR=$<TARGET_FILE:geovor_cli> -DINPUT=${file} -DOUT=${robust_out}
            -DNAME=${name} -DROWS=${rows} -DSITES=${sites} -DMERGED=${merged} -DREJECTED=${rejected}
            "-DEXTRA=${extra}" -DCHECK_ROW_NUMBERS=${each} -P ${check_accounting}
    WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
  set_tests_properties(cli.rows.${name} PROPERTIES LABELS cli)
endfunction()

# The fixtures of datasets/fixtures/ (counts as in tests/cli/CMakeLists.txt) and the real data.
geovor_cli_rows(weather_stations ${stations} 5634 5631 3 0)
geovor_cli_rows(one_site ${fixtures}/one_site.csv 1 1 0 0)
geovor_cli_rows(two_sites ${fixtures}/two_sites.csv 2 2 0 0)          # two antipodal sites
geovor_cli_rows(three_sites ${fixtures}/three_sites.csv 3 3 0 0)
geovor_cli_rows(equator ${fixtures}/equator.csv 12 12 0 0)            # all on one great circle
geovor_cli_rows(small_circle ${fixtures}/small_circle.csv 12 12 0 0)
geovor_cli_rows(hemisphere ${fixtures}/hemisphere.csv 20 20 0 0)
geovor_cli_rows(cube_corners ${fixtures}/cube_corners.csv 8 8 0 0)
geovor_cli_rows(duplicates ${fixtures}/duplicates.csv 5 3 2 0)
geovor_cli_rows(antimeridian ${fixtures}/antimeridian.csv 13 8 5 0)   # lon 180, -180, 540, -540
geovor_cli_rows(poles ${fixtures}/poles.csv 16 10 6 0)
geovor_cli_rows(bad_rows ${fixtures}/bad_rows.csv 12 4 0 8)
# tests/cli/fixtures/:
# header_only.csv: no row.
geovor_cli_rows(lon_180 ${robust_fixtures}/lon_180.csv 5 3 2 0)
geovor_cli_rows(header_only ${robust_fixtures}/header_only.csv 0 0 0 0)
# bad_values.csv: 23 rows; 6 accepted (ok; " 30 , +40 " with spaces and a plus sign; lat 90 and
# -90 with any longitude; lon 540 and -540), 17 rejected (NaN, nan, inf, -Infinity, lat 1e308,
# lon 1e308, 1e309, lat 91, lat -90.0000001, lon 1000, lon 540.0000001, abc, 0x10, empty, spaces
# only, 2 fields, 4 fields). No two accepted rows share a position.
geovor_cli_rows(bad_values ${robust_fixtures}/bad_values.csv 23 6 0 17)
# crlf_bom.csv: 4 rows (an empty line between rows 2 and 3 is no row; the last has no line end).
geovor_cli_rows(crlf_bom ${robust_fixtures}/crlf_bom.csv 4 4 0 0)
# quoted.csv: rows 1-4 with quoted commas, LF and CRLF inside quotes, doubled quotes; row 5 an
# unterminated quote running to the end of the file: rejected.
geovor_cli_rows(quoted ${robust_fixtures}/quoted.csv 5 4 0 1)
# near_duplicates.csv: a_10cm is 0.0994 m from a (merged: under 2^-24 R = 0.38 m); a_1m is 1.1 m
# away (a site; merged too with --merge-m 2).
geovor_cli_rows(near_duplicates ${robust_fixtures}/near_duplicates.csv 4 3 1 0)
geovor_cli_rows(near_duplicates_merge_2m ${robust_fixtures}/near_duplicates.csv 4 2 2 0 --merge-m 2)
# duplicate_ids.csv: id X three times (rows 1 and 3 at one position: merged), Y once.
geovor_cli_rows(duplicate_ids ${robust_fixtures}/duplicate_ids.csv 4 3 1 0)
# non_point.geojson: 9 features; Point, MultiPoint of one point and another Point are sites;
# LineString, Polygon, null, MultiPoint of 2, GeometryCollection and a point at latitude 95 rejected.
geovor_cli_rows(non_point ${robust_fixtures}/non_point.geojson 9 3 0 6)
# polygons_only.geojson: an OGR layer without a point: every feature rejected, no cell.
geovor_cli_rows(polygons_only ${robust_fixtures}/polygons_only.geojson 2 0 0 2)
# Generated (make_big_fixtures.cmake): 10^6 rows at one position, one cell; the 10 MB lines.
geovor_cli_rows(identical_1e6 ${big}/identical_1e6.csv 1000000 1 999999 0)
geovor_cli_rows(long_lines ${big}/long_lines.csv 5 3 0 2)
robust_needs_big(cli.rows.identical_1e6 cli.rows.long_lines)
# The bundled cities, gzip-compressed, read through GDAL's /vsigzip/ (171,075 rows,
# datasets/README.md; 37 share a position with an earlier one).
geovor_cli_rows(cities_vsigzip /vsigzip/datasets/geonames_cities.csv.gz 171075 171038 37 0)

# ------------------------------------------------------------------------------------------------
# Inputs refused as a whole, with the file and the reason; nothing written.
geovor_cli_expect(cli.robust.empty_file 3 STDERR "empty\\.csv: empty file, no header"
  COMMAND info ${robust_fixtures}/empty.csv)
geovor_cli_expect(cli.robust.empty_file_cells 3 STDERR "empty\\.csv: empty file, no header"
  COMMAND cells ${robust_fixtures}/empty.csv -o ${robust_out}/never_empty.geojson)
add_test(NAME cli.robust.empty_file_cells.nothing_written
  COMMAND ${CMAKE_COMMAND} -E cat ${robust_out}/never_empty.geojson)
set_tests_properties(cli.robust.empty_file_cells.nothing_written PROPERTIES LABELS cli WILL_FAIL ON
  DEPENDS cli.robust.empty_file_cells)
geovor_cli_expect(cli.robust.no_lat_lon_columns 3
  STDERR "no_lat_lon\\.csv: no latitude/longitude columns; looked for names such as lat, latitude, stop_lat, decimalLatitude, LATITUDE_DEG, POINT_Y, y and lon, lng, long, longitude, stop_lon, decimalLongitude, POINT_X, x; found columns: id, easting_m, northing_m; use --lat-field/--lon-field"
  COMMAND info ${robust_fixtures}/no_lat_lon.csv)
# Header only: no site, so every command stops with exit 3 before writing anything.
geovor_cli_expect(cli.robust.header_only_info 3 STDERR "header_only\\.csv: no usable site \\(0 rows, 0 rejected\\): the table has no data row"
  COMMAND info ${robust_fixtures}/header_only.csv)
geovor_cli_expect(cli.robust.header_only_cells 3 STDOUT "^$" STDERR "header_only\\.csv: no usable site"
  COMMAND cells ${robust_fixtures}/header_only.csv -o - -q)
geovor_cli_expect(cli.robust.header_only_nearest 3 STDERR "header_only\\.csv: no usable site \\(0 rows, 0 rejected\\)"
  COMMAND nearest --sites ${robust_fixtures}/header_only.csv --queries ${robust_fixtures}/empty.csv)
geovor_cli_expect(cli.robust.polygons_only_nearest 3
  STDERR "polygons_only\\.geojson: row 2 rejected: feature 2 \\(FID 1\\): geometry is a Polygon, not a Point\n.*polygons_only\\.geojson: no usable site \\(2 rows, 2 rejected\\)"
  COMMAND nearest --sites ${robust_fixtures}/polygons_only.geojson --queries ${robust_fixtures}/empty.csv)

# Rejected rows: each names the file, the row, the line, the column and the reason.
set(bv "[^\n]*bad_values\\.csv: row")
geovor_cli_expect(cli.robust.bad_values 0
  STDERR "${bv} 2 \\(line 3\\) rejected: lat: latitude is not a finite number\n${bv} 3 \\(line 4\\) rejected: lat: latitude is not a finite number\n${bv} 4 \\(line 5\\) rejected: lon: longitude is not a finite number\n${bv} 5 \\(line 6\\) rejected: lat: latitude is not a finite number\n${bv} 6 \\(line 7\\) rejected: lat: latitude 1e\\+308 is beyond \\+-90\n${bv} 7 \\(line 8\\) rejected: lon: longitude 1e\\+308 is out of range \\[-540, 540\\]\n${bv} 8 \\(line 9\\) rejected: lat: '1e309' is out of the range of a double\n${bv} 9 \\(line 10\\) rejected: lat: latitude 91 is beyond \\+-90\n${bv} 10 \\(line 11\\) rejected: lat: latitude -90\\.0000001 is beyond \\+-90\n${bv} 11 \\(line 12\\) rejected: lon: longitude 1000 is out of range \\[-540, 540\\]\n${bv} 12 \\(line 13\\) rejected: lon: longitude 540\\.0000001 is out of range \\[-540, 540\\]\n${bv} 13 \\(line 14\\) rejected: lat: 'abc' is not a number\n${bv} 14 \\(line 15\\) rejected: lat: '0x10' is not a number\n${bv} 15 \\(line 16\\) rejected: lat: empty value\n${bv} 16 \\(line 17\\) rejected: lat: empty value\n${bv} 17 \\(line 18\\) rejected: found 2 fields, expected 3 as in the header \\(no value for lon\\)\n${bv} 18 \\(line 19\\) rejected: found 4 fields, expected 3 as in the header\n"
  COMMAND info ${robust_fixtures}/bad_values.csv)
# The poles at any longitude and longitudes 540/-540 are accepted: nearest answers each at 0 m.
file(WRITE ${robust_out}/pole_queries.csv "id,lat,lon\nnp,90,0\nsp,-90,77\nlon_m180,-30,-180\nlon_180b,-31,180\n")
geovor_cli_expect(cli.robust.poles_and_540 0
  STDOUT "\nnp,[0-9]+,north_pole,0,np,90,0\nsp,[0-9]+,south_pole,0,sp,-90,77\nlon_m180,[0-9]+,lon_540,0,lon_m180,-30,-180\nlon_180b,[0-9]+,lon_-540,0,lon_180b,-31,180\n$"
  COMMAND nearest --sites ${robust_fixtures}/bad_values.csv --queries ${robust_out}/pole_queries.csv)
# lon 180, -180 and 540 are one point (longitudes are reduced to [-180, 180)): lon_180.csv has
# them at latitude 10 (rows a, b, c), merged into one site.
geovor_cli_expect(cli.robust.lon_180_-180_540 0
  STDOUT "\nrows: 5\nsites: 3\nmerged: 2\nrejected: 0\n"
  STDERR "lon_180\\.csv: row 2 \\(id b\\) merged into the site of row 1 \\(id a\\): same position\n[^\n]*lon_180\\.csv: row 3 \\(id c\\) merged into the site of row 1 \\(id a\\): same position\n$"
  COMMAND info ${robust_fixtures}/lon_180.csv)

# CRLF and a byte order mark: the BOM is not part of the first column's name (so `id` is found
# and the ids are a, b, c, d, not row numbers) and no value keeps a CR.
geovor_cli_expect(cli.robust.crlf_bom 0
  STDOUT "\"site_id\":\"a\".*\"site_id\":\"b\".*\"site_id\":\"c\".*\"site_id\":\"d\",[^\n]*\"id\":\"d\",\"lat\":5,\"lon\":6}"
  COMMAND cells ${robust_fixtures}/crlf_bom.csv -o - -q)
# Quoted fields keep their commas, quotes and line breaks (LF and CRLF), and lines are counted
# inside them: row 4 is on line 7, the unterminated quote of row 5 starts on line 8.
geovor_cli_expect(cli.robust.quoted_fields 0
  STDOUT "\"name\":\"Paris, France\".*\"name\":\"multi\\\\nline \\\\\"quoted\\\\\" name\".*\"name\":\"crlf\\\\r\\\\ninside\".*\"name\":\"plain\""
  STDERR "quoted\\.csv: row 5 \\(line 8\\) rejected: name: unterminated quoted field starting on line 8"
  COMMAND cells ${robust_fixtures}/quoted.csv -o -)
geovor_cli_expect(cli.robust.quoted_report 0
  COMMAND cells ${robust_fixtures}/quoted.csv -o ${robust_out}/quoted.geojson --overwrite -q
          --report ${robust_out}/quoted_lines.csv)
add_test(NAME cli.robust.quoted_report.lines COMMAND ${CMAKE_COMMAND} -E cat ${robust_out}/quoted_lines.csv)
set_tests_properties(cli.robust.quoted_report.lines PROPERTIES LABELS cli DEPENDS cli.robust.quoted_report
  PASS_REGULAR_EXPRESSION "\n1,2,\"1\",site,0,\n2,3,\"2\",site,1,\n3,5,\"3\",site,2,\n4,7,\"4\",site,3,\n5,8,,rejected,,\"name: unterminated")

# 10 MB lines: a 10 MB name is kept, a 10 MB field alone and a 10 MB number are rejected with
# their value cut to 40 characters in the message.
geovor_cli_expect(cli.robust.long_lines 0
  STDOUT "\nrows: 5\nsites: 3\nmerged: 0\nrejected: 2\n"
  STDERR "long_lines\\.csv: row 3 \\(line 4\\) rejected: found 2 fields, expected 4 as in the header \\(no value for lat, lon\\)\n[^\n]*long_lines\\.csv: row 5 \\(line 6\\) rejected: lat: '9999999999999999999999999999999999999999\\.\\.\\.' \\(10000000 characters\\) is out of the range of a double\n"
  COMMAND info ${big}/long_lines.csv)
geovor_cli_expect(cli.robust.long_query_lines 0
  STDOUT "^query_id,site_index,site_id,distance_m,lat,lon\n2,[^\n]*\n3,,,,9999999999[^\n]*\n4,,,,,\n5,[^\n]*\n$"
  STDERR "long_query_lines\\.csv: line 3: lat: '9999999999999999999999999999999999999999\\.\\.\\.' \\(10000000 characters\\) is out of the range of a double\n.*line 4: expected 2 fields, found 1\ngeovor nearest: 2 queries answered \\(0 without a site within --max-distance-m\\), 2 malformed \\(written with an empty match\\)"
  COMMAND nearest --sites ${fixtures}/three_sites.csv --queries ${big}/long_query_lines.csv)
# 10^6 identical points: one site, the whole Earth its cell, 999,999 merges listed.
geovor_cli_expect(cli.robust.identical_1e6 0
  STDOUT "\nrows: 1000000\nsites: 1\nmerged: 999999\nrejected: 0\ntriangles: 0\n.*degenerate: one site\nvalid: yes"
  STDERR "identical_1e6\\.csv: row 1000000 \\(id 1000000\\) merged into the site of row 1 \\(id 1\\): same position\n$"
  COMMAND info ${big}/identical_1e6.csv)
# Queries with CRLF, a BOM, an empty line and no final line end.
geovor_cli_expect(cli.robust.queries_crlf_bom 0
  STDOUT "^query_id,site_index,site_id,distance_m,id,lat,lon\nq1,0,a,0,q1,10,20\nq2,1,b,0,q2,-10,30\n$"
  COMMAND nearest --sites ${robust_fixtures}/crlf_bom.csv --queries ${big}/queries_crlf_bom.csv)
robust_needs_big(cli.robust.long_lines cli.robust.long_query_lines cli.robust.identical_1e6 cli.robust.queries_crlf_bom)
# An empty query stream: the header and nothing else.
geovor_cli_expect(cli.robust.no_queries 0 STDOUT "^query_id,site_index,site_id,distance_m\n$"
  COMMAND nearest --sites ${robust_fixtures}/crlf_bom.csv --queries ${robust_fixtures}/empty.csv)

# Degenerate sets: one great circle, two antipodal points (their cells are hemispheres).
geovor_cli_expect(cli.robust.great_circle 0 STDOUT "\ndegenerate: all sites on one great circle\nvalid: yes\n"
  COMMAND info ${fixtures}/equator.csv)
geovor_cli_expect(cli.robust.antipodal 0 STDOUT "\ndegenerate: two sites\nvalid: yes\n"
  COMMAND info ${fixtures}/two_sites.csv)

# Near-duplicates and duplicate ids.
geovor_cli_expect(cli.robust.near_duplicates 0
  STDERR "near_duplicates\\.csv: row 2 \\(id a_10cm\\) merged into the site of row 1 \\(id a\\): 0\\.0994 m apart, closer than the merge distance\n$"
  COMMAND info ${robust_fixtures}/near_duplicates.csv)
geovor_cli_expect(cli.robust.near_duplicates_merge_2m 0
  STDERR "row 3 \\(id a_1m\\) merged into the site of row 1 \\(id a\\): 1\\.1 m apart"
  COMMAND info ${robust_fixtures}/near_duplicates.csv --merge-m 2)
# Duplicate ids are kept as they are: two sites answer `X`, told apart by site_index.
file(WRITE ${robust_out}/dup_queries.csv "id,lat,lon\nfirst,10,10\nsecond,-10,-10\n")
geovor_cli_expect(cli.robust.duplicate_ids 0 STDOUT "\nfirst,0,X,0,first,10,10\nsecond,1,X,0,second,-10,-10\n$"
  COMMAND nearest --sites ${robust_fixtures}/duplicate_ids.csv --queries ${robust_out}/dup_queries.csv)

# OGR: non-point geometries rejected with the feature number, FID and geometry type.
set(np "[^\n]*non_point\\.geojson: row")
geovor_cli_expect(cli.robust.non_point_geometries 0
  STDOUT "\nrows: 9\nsites: 3\nmerged: 0\nrejected: 6\n"
  STDERR "${np} 2 rejected: feature 2 \\(FID 1\\): geometry is a Line String, not a Point\n${np} 3 rejected: feature 3 \\(FID 2\\): geometry is a Polygon, not a Point\n${np} 4 rejected: feature 4 \\(FID 3\\): geometry is null\n${np} 6 rejected: feature 6 \\(FID 5\\): geometry is a MultiPoint of 2 points, not a Point\n${np} 7 rejected: feature 7 \\(FID 6\\): geometry is a Geometry Collection, not a Point\n${np} 8 rejected: feature 8 \\(FID 7\\): latitude 95 is beyond \\+-90\n"
  COMMAND info ${robust_fixtures}/non_point.geojson)

# Compressed input: gzip data in a .csv, and a .csv.gz GDAL cannot open by itself (the message
# says how: /vsigzip/, tested by cli.rows.cities_vsigzip).
file(ARCHIVE_CREATE OUTPUT ${robust_out}/three_sites.csv.gz PATHS ${PROJECT_SOURCE_DIR}/${fixtures}/three_sites.csv
  FORMAT raw COMPRESSION GZip)
configure_file(${robust_out}/three_sites.csv.gz ${robust_out}/gzip_inside.csv COPYONLY)
geovor_cli_expect(cli.robust.gzip_named_csv 3 STDERR "gzip_inside\\.csv: gzip-compressed data, not CSV; decompress it first"
  COMMAND info ${robust_out}/gzip_inside.csv)
geovor_cli_expect(cli.robust.csv_gz 3 STDERR "three_sites\\.csv\\.gz: gzip-compressed; decompress it \\(gzip -dk [^)]*\\) or give it to GDAL as /vsigzip/"
  COMMAND info ${robust_out}/three_sites.csv.gz)
geovor_cli_expect(cli.robust.vsigzip 0 STDOUT "\nrows: 3\nsites: 3\n"
  COMMAND info /vsigzip/${robust_out}/three_sites.csv.gz)

# Standard input.
geovor_cli_expect(cli.robust.stdin 0 STDOUT "input: <stdin>\nrows: 3\nsites: 3\n"
  SCRIPT "exec \"$0\" info - < ${fixtures}/three_sites.csv")
geovor_cli_expect(cli.robust.stdin_twice 2 STDERR "--sites and --queries cannot both be standard input"
  COMMAND nearest --sites - --queries -)

# Column options naming nothing (usage errors, exit 2).
geovor_cli_expect(cli.robust.bad_lat_field 2
  STDERR "bad_values\\.csv: latitude field 'nosuch' is not a column; found columns: id, lat, lon"
  COMMAND info ${robust_fixtures}/bad_values.csv --lat-field nosuch)
geovor_cli_expect(cli.robust.bad_id_field 2 STDERR "bad_values\\.csv: id field 'nosuch' is not a column"
  COMMAND cells ${robust_fixtures}/bad_values.csv -o ${robust_out}/never_id.geojson --id-field nosuch)
geovor_cli_expect(cli.robust.bad_ecef_fields 2 STDERR "ECEF input needs exactly 3 columns \\(X, Y, Z\\), got 2: a, b"
  COMMAND info ${robust_fixtures}/bad_values.csv --ecef-fields a,b)
geovor_cli_expect(cli.robust.ecef_and_lat 2 STDERR "ECEF columns and latitude/longitude columns cannot both be given"
  COMMAND info ${robust_fixtures}/bad_values.csv --ecef-fields X,Y,Z --lat-field lat)

# ------------------------------------------------------------------------------------------------
# Unreadable inputs (as root too: no permission bits involved), exit 4 with the path and errno.
file(MAKE_DIRECTORY ${robust_out}/a_directory.csv)
geovor_cli_expect(cli.robust.input_is_directory 4 STDERR "a_directory\\.csv: cannot read: Is a directory"
  COMMAND info ${robust_out}/a_directory.csv)
geovor_cli_expect(cli.robust.input_missing 4 STDERR "no_such\\.csv: cannot open: No such file or directory"
  COMMAND cells ${robust_out}/no_such.csv -o ${robust_out}/never_missing.geojson)
geovor_cli_expect(cli.robust.input_not_a_directory 4 STDERR "empty\\.csv/x\\.csv: cannot open: Not a directory"
  COMMAND info ${robust_fixtures}/empty.csv/x.csv)
# /proc/self/mem opens, but reading its first page fails (EIO): a read error midway.
file(CREATE_LINK /proc/self/mem ${robust_out}/unreadable.csv RESULT link_result SYMBOLIC)
geovor_cli_expect(cli.robust.read_error 4 STDERR "unreadable\\.csv: read error near line 1"
  COMMAND info ${robust_out}/unreadable.csv)
# (Through the .csv link: a query file of another name is read as an OGR layer, as sites are.)
geovor_cli_expect(cli.robust.queries_read_error 4 STDERR "unreadable\\.csv: read error: Input/output error"
  COMMAND nearest --sites ${fixtures}/three_sites.csv --queries ${robust_out}/unreadable.csv)
geovor_cli_expect(cli.robust.queries_directory 4 STDERR "a_directory\\.csv: read error: Is a directory"
  COMMAND nearest --sites ${fixtures}/three_sites.csv --queries ${robust_out}/a_directory.csv)

# ------------------------------------------------------------------------------------------------
# Existing outputs: refused without --overwrite before any work, the file untouched.
file(WRITE ${robust_out}/keep.csv "keep me\n")
geovor_cli_expect(cli.robust.report_exists 4 STDERR "keep\\.csv: exists; use --overwrite to replace it"
  COMMAND cells ${fixtures}/three_sites.csv -o ${robust_out}/never_report.geojson --report ${robust_out}/keep.csv)
# No cells were written either (the report is checked first), and keep.csv is unchanged.
add_test(NAME cli.robust.report_exists.nothing_written COMMAND ${CMAKE_COMMAND} -E cat ${robust_out}/never_report.geojson)
set_tests_properties(cli.robust.report_exists.nothing_written PROPERTIES LABELS cli WILL_FAIL ON
  DEPENDS cli.robust.report_exists)
add_test(NAME cli.robust.outputs_untouched COMMAND ${CMAKE_COMMAND} -E cat ${robust_out}/keep.csv)
set_tests_properties(cli.robust.outputs_untouched PROPERTIES LABELS cli
  PASS_REGULAR_EXPRESSION "^keep me\n$" DEPENDS "cli.robust.report_exists;cli.robust.nearest_exists")
geovor_cli_expect(cli.robust.nearest_exists 4 STDERR "keep\\.csv: exists; use --overwrite to replace it"
  COMMAND nearest --sites ${fixtures}/three_sites.csv --queries ${fixtures}/three_sites.csv -o ${robust_out}/keep.csv)
geovor_cli_expect(cli.robust.output_is_directory 4 STDERR "a_directory\\.csv: is a directory"
  COMMAND nearest --sites ${fixtures}/three_sites.csv --queries ${fixtures}/three_sites.csv
          -o ${robust_out}/a_directory.csv --overwrite)

# Devices are written in place, never replaced by a rename (as root that would replace /dev/null);
# the formats that need a regular file say so.
geovor_cli_expect(cli.robust.output_dev_null 0
  COMMAND nearest --sites ${fixtures}/three_sites.csv --queries ${fixtures}/three_sites.csv -o /dev/null)
geovor_cli_expect(cli.robust.cells_dev_null 0
  COMMAND cells ${fixtures}/three_sites.csv -o /dev/null --format GeoJSON -q)
geovor_cli_expect(cli.robust.gpkg_dev_null 4 STDERR "/dev/null: not a regular file; GPKG output must be one"
  COMMAND cells ${fixtures}/three_sites.csv -o /dev/null --format GPKG --overwrite -q)
geovor_cli_expect(cli.robust.index_dev_null 4 STDERR "/dev/null: not a regular file; an index must be one"
  COMMAND index ${fixtures}/three_sites.csv -o /dev/null --overwrite)
add_test(NAME cli.robust.dev_null_still_a_device COMMAND test -c /dev/null)
set_tests_properties(cli.robust.dev_null_still_a_device PROPERTIES LABELS cli
  DEPENDS "cli.robust.output_dev_null;cli.robust.cells_dev_null;cli.robust.gpkg_dev_null;cli.robust.index_dev_null")

# ------------------------------------------------------------------------------------------------
# A full disk. /dev/full as stdout: every command fails with exit 4 (info's and index's summaries
# included: geovor checks what it wrote to stdout).
foreach(cmd info cells nearest index)
  if(cmd STREQUAL "info")
    set(args "info ${fixtures}/three_sites.csv")
  elseif(cmd STREQUAL "cells")
    set(args "cells ${fixtures}/three_sites.csv -o - -q")
  elseif(cmd STREQUAL "nearest")
    set(args "nearest --sites ${fixtures}/three_sites.csv --queries ${fixtures}/three_sites.csv")
  else()
    set(args "index ${fixtures}/three_sites.csv -o ${robust_out}/full_stdout.gvi --overwrite")
  endif()
  geovor_cli_expect(cli.robust.dev_full_stdout.${cmd} 4 STDERR "(<stdout>|-): (write error|cannot write to stdout): No space left on device"
    SCRIPT "exec \"$0\" ${args} > /dev/full")
endforeach()
# /dev/full as the target (a device: written in place).
geovor_cli_expect(cli.robust.dev_full_target.nearest 4 STDERR "/dev/full: write error: No space left on device"
  COMMAND nearest --sites ${stations} --queries ${stations} -o /dev/full)
geovor_cli_expect(cli.robust.dev_full_target.cells 4 STDERR "/dev/full: cannot write: No space left on device"
  COMMAND cells ${stations} -o /dev/full --format GeoJSON -q)
# A really full file system: a 64 KiB tmpfs (skipped where it cannot be mounted), and a 64 KiB
# file size limit (any user). Every output format: exit 4, the file and reason named, nothing
# left behind (no target, no temporary file).
set(full_disk_cases
  "cells_geojson|cells.geojson||cells|${stations}|-o|@OUT@|-q"
  "cells_geojsonseq|cells.geojsonl||cells|${stations}|-o|@OUT@|-q"
  "cells_gpkg|cells.gpkg|cannot [a-z]+ |cells|${stations}|-o|@OUT@|-q"
  "cells_fgb|cells.fgb|cannot write feature|cells|${stations}|-o|@OUT@|-q"
  "cells_shp|cells.shp|cannot write feature|cells|${stations}|-o|@OUT@|-q"
  "cells_csv|cells.csv||cells|${stations}|-o|@OUT@|-q"
  "report|report.csv||cells|${stations}|-o|/dev/null|--format|GeoJSON|-q|--report|@OUT@"
  "nearest|nearest.csv||nearest|--sites|${stations}|--queries|${stations}|-o|@OUT@"
  "index|stations.gvi||index|${stations}|-o|@OUT@")
foreach(case IN LISTS full_disk_cases)
  string(REPLACE "|" ";" parts "${case}")
  list(POP_FRONT parts name target reason)
  list(JOIN parts "|" args)
  foreach(mode tmpfs fsize)
    set(defs -DGEOVOR=$<TARGET_FILE:geovor_cli> -DMODE=${mode} -DDIR=${robust_out}/full_${mode}_${name}
             -DTARGET=${target} "-DARGS=${args}")
    if(reason)
      list(APPEND defs "-DREASON=${reason}")
    endif()
    add_test(NAME cli.robust.full_disk.${mode}.${name}
      COMMAND ${CMAKE_COMMAND} ${defs} -P ${full_disk}
      WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
    set_tests_properties(cli.robust.full_disk.${mode}.${name} PROPERTIES LABELS cli
      SKIP_REGULAR_EXPRESSION "SKIPPED:")
  endforeach()
endforeach()

# ------------------------------------------------------------------------------------------------
# Load: 3 x 10^6 generated queries through `geovor nearest`; its peak resident memory after all
# of them exceeds the peak after the first 10^6 by less than max(4 MiB, 5 %) (nothing is timed;
# bench/nearest_soak.cpp, the 10^8-query soak, is the same program).
add_executable(geovor_test_nearest_soak ${PROJECT_SOURCE_DIR}/bench/nearest_soak.cpp)
target_compile_options(geovor_test_nearest_soak PRIVATE -Wall -Wextra)
add_test(NAME cli.robust.nearest_constant_memory
  COMMAND geovor_test_nearest_soak --geovor $<TARGET_FILE:geovor_cli> --sites ${stations}
          --queries 3000000 --first 1000000 --interval 1000 --check-constant-memory
  WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
# nosan: ASan keeps freed memory in quarantine, so the peak grows with the work done.
set_tests_properties(cli.robust.nearest_constant_memory PROPERTIES LABELS "cli;nosan")
