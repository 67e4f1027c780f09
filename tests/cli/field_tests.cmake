# Field types, names and values as GDAL reads them back (issue 16): every expected type and value
# is from datasets/fixtures/typed_columns.csv by hand (datasets/README.md), read back by ogrinfo.
set(fields_out ${CMAKE_CURRENT_BINARY_DIR}/fields)
file(MAKE_DIRECTORY ${fields_out})
set(typed ${fixtures}/typed_columns.csv)
set(has_fields "sh ${CMAKE_CURRENT_SOURCE_DIR}/has_fields.sh")

# CSV columns typed by their values; identifiers (the id column, leading zeros) stay text; an
# all-empty column is String; fid, GEOM and area_m2 renamed src_* (GeoPackage refused fid/geom).
geovor_cli_expect(cli.fields.csv_types_gpkg 0 SCRIPT
  "rm -f ${fields_out}/t.gpkg && \"$0\" cells ${typed} -o ${fields_out}/t.gpkg -q && ${has_fields} ${fields_out}/t.gpkg 'site_index: Integer64' 'ids: String(JSON)' 'neighbors: String(JSON)' 'id: String' 'name: String' 'lat: Real' 'lon: Real' 'pop: Integer' 'big: Integer64' 'elev: Real' 'founded: Date' 'updated: DateTime' 'zip: String' 'note: String' 'src_fid: Integer' 'src_GEOM: String' 'src_area_m2: Real'")
# Values: an empty Integer or Date is NULL; a Real, a date and a zip code read back as written.
geovor_cli_expect(cli.fields.csv_values_gpkg 0 STDOUT "pop \\(Integer\\) = \\(null\\).*big \\(Integer64\\) = 1\n.*elev \\(Real\\) = -3\n.*founded \\(Date\\) = 1850/12/31\n.*updated \\(DateTime\\) = 2024/03/01 00:00:00\\+00\n.*zip \\(String\\) = 90210" SCRIPT
  "rm -f ${fields_out}/v.gpkg && \"$0\" cells ${typed} -o ${fields_out}/v.gpkg -q && ogrinfo -ro -q ${fields_out}/v.gpkg -sql \"SELECT pop, big, elev, founded, updated, zip FROM cells WHERE id = '002'\"")
geovor_cli_expect(cli.fields.csv_null_date 0 STDOUT "founded \\(Date\\) = \\(null\\)" SCRIPT
  "rm -f ${fields_out}/d.gpkg && \"$0\" cells ${typed} -o ${fields_out}/d.gpkg -q && ogrinfo -ro -q ${fields_out}/d.gpkg -sql \"SELECT founded FROM cells WHERE id = '003'\"")
# The bundled stations' coordinates are Real.
geovor_cli_expect(cli.fields.weather_stations_real 0 SCRIPT
  "rm -f ${fields_out}/w.fgb && \"$0\" cells datasets/weather_stations.csv -o ${fields_out}/w.fgb -q 2>/dev/null && ${has_fields} ${fields_out}/w.fgb 'icao: String' 'name: String' 'lat_deg: Real' 'lon_deg: Real'")
# --all-text keeps every column String.
geovor_cli_expect(cli.fields.all_text 0 SCRIPT
  "rm -f ${fields_out}/a.gpkg && \"$0\" cells ${typed} -o ${fields_out}/a.gpkg -q --all-text && ${has_fields} ${fields_out}/a.gpkg 'lat: String' 'pop: String' 'founded: String' 'src_fid: String' 'n_rows: Integer64'")
# FlatGeobuf and Shapefile in their own types. FlatGeobuf stores a Date as a DateTime (its driver
# does: GDAL reads it back so); a Shapefile has no DateTime: String (the nearest type that loses
# nothing), as text; GDAL reads a DBF integer 10 digits wide (2147483647) back as Integer64.
geovor_cli_expect(cli.fields.csv_types_fgb 0 SCRIPT
  "rm -f ${fields_out}/t.fgb && \"$0\" cells ${typed} -o ${fields_out}/t.fgb -q && ${has_fields} ${fields_out}/t.fgb 'pop: Integer' 'big: Integer64' 'elev: Real' 'founded: DateTime' 'updated: DateTime' 'zip: String' 'src_fid: Integer'")
geovor_cli_expect(cli.fields.csv_types_shp 0 SCRIPT
  "rm -f ${fields_out}/t.shp ${fields_out}/t.dbf ${fields_out}/t.shx ${fields_out}/t.prj ${fields_out}/t.cpg && \"$0\" cells ${typed} -o ${fields_out}/t.shp -q 2>/dev/null && ${has_fields} ${fields_out}/t.shp 'pop: Integer64' 'big: Integer64' 'elev: Real' 'founded: Date' 'updated: String' 'zip: String' 'src_fid: Integer' && ogrinfo -ro -q ${fields_out}/t.shp -sql \"SELECT updated FROM t WHERE id = '001'\" | grep -q 'updated (String) = 2024-02-29T13:05:00Z'")
# GeoJSON: numbers unquoted, identifiers quoted, ids and neighbors JSON arrays, empty values null.
geovor_cli_expect(cli.fields.geojson_numbers 0 SCRIPT
  "rm -f ${fields_out}/t.geojson && \"$0\" cells ${typed} -o ${fields_out}/t.geojson -q && grep -qF '\"id\":\"002\",\"bbox\"' ${fields_out}/t.geojson && grep -q '\"ids\":.\"001\".,\"n_rows\":1,' ${fields_out}/t.geojson && grep -q '\"neighbors\":.\"00' ${fields_out}/t.geojson && grep -qF '\"id\":\"002\",\"name\":\"Beta\",\"lat\":-33.25,\"lon\":151,\"pop\":null,\"big\":1,\"elev\":-3,\"founded\":\"1850-12-31\",\"updated\":\"2024-03-01T00:00:00Z\",\"zip\":\"90210\",\"note\":\"\",\"src_fid\":2,\"src_GEOM\":\"g2\",\"src_area_m2\":2}' ${fields_out}/t.geojson")
# GDAL reads the GeoJSON arrays back as lists.
geovor_cli_expect(cli.fields.geojson_arrays_for_gdal 0 SCRIPT
  "rm -f ${fields_out}/l.geojson && \"$0\" cells ${typed} -o ${fields_out}/l.geojson -q && ${has_fields} ${fields_out}/l.geojson 'ids: StringList' 'neighbors: StringList' 'pop: Integer' 'big: Integer64'")
# An OGR input keeps its fields' types (here GDAL's own detection of the CSV's).
geovor_cli_expect(cli.fields.ogr_input_types 0 SCRIPT
  "rm -f ${fields_out}/in.gpkg ${fields_out}/o.fgb && ogr2ogr -f GPKG ${fields_out}/in.gpkg ${typed} -oo X_POSSIBLE_NAMES=lon -oo Y_POSSIBLE_NAMES=lat -oo AUTODETECT_TYPE=YES -select name,pop,elev,founded,updated && \"$0\" cells ${fields_out}/in.gpkg -o ${fields_out}/o.fgb -q && ${has_fields} ${fields_out}/o.fgb 'name: String' 'pop: Integer' 'elev: Real' 'updated: DateTime' && ${has_fields} ${fields_out}/in.gpkg 'name: String' 'pop: Integer' 'elev: Real' 'updated: DateTime'")
# relax --sites-output carries the types too.
geovor_cli_expect(cli.fields.sites_output_types 0 SCRIPT
  "rm -f ${fields_out}/c.gpkg ${fields_out}/s.gpkg && \"$0\" relax ${typed} -o ${fields_out}/c.gpkg --sites-output ${fields_out}/s.gpkg -n 1 -q && ${has_fields} ${fields_out}/s.gpkg 'site_index: Integer64' 'pop: Integer' 'updated: DateTime' 'src_fid: Integer'")

# Each test writes its own copy: tests run in parallel, and two appending to one file made 120 rows.
function(many_rows out csv)
  set(${out} "printf 'id,lat,lon\\nother,-10,-20\\nthird,0,100\\n' > ${csv} && seq 1 60 | sed 's/.*/row_&,10,20/' >> ${csv}" PARENT_SCOPE)
endfunction()
# Shapefile: nothing cut. 60 rows at one position make an ids list of 60 * 9 bytes: refused with
# the limit and a format that holds it (exit 3), nothing written.
many_rows(rows_shp_long_ids_refused ${fields_out}/shp_long_ids_refused.csv)
geovor_cli_expect(cli.fields.shp_long_ids_refused 3 STDERR "field 'ids': [0-9]+ bytes, but a field of format ESRI Shapefile holds at most 254 bytes .the value would be cut.. write GeoPackage" SCRIPT
  "${rows_shp_long_ids_refused} && rm -f ${fields_out}/m.shp && \"$0\" cells ${fields_out}/shp_long_ids_refused.csv -o ${fields_out}/m.shp -q")
many_rows(rows_shp_long_ids_nothing_written ${fields_out}/shp_long_ids_nothing_written.csv)
geovor_cli_expect(cli.fields.shp_long_ids_nothing_written 0 SCRIPT
  "${rows_shp_long_ids_nothing_written} && rm -f ${fields_out}/m2.* && ! \"$0\" cells ${fields_out}/shp_long_ids_nothing_written.csv -o ${fields_out}/m2.shp -q 2>/dev/null && ! ls ${fields_out}/m2.* 2>/dev/null && ! ls -a ${fields_out} | grep -q 'm2.*tmp'")
# The same ids in full in a GeoPackage.
many_rows(rows_gpkg_long_ids_whole ${fields_out}/gpkg_long_ids_whole.csv)
geovor_cli_expect(cli.fields.gpkg_long_ids_whole 0 STDOUT "v \\(Integer\\) = 60" SCRIPT
  "${rows_gpkg_long_ids_whole} && rm -f ${fields_out}/m.gpkg && \"$0\" cells ${fields_out}/gpkg_long_ids_whole.csv -o ${fields_out}/m.gpkg -q && ogrinfo -ro -q ${fields_out}/m.gpkg -dialect SQLite -sql \"SELECT json_array_length(ids) AS v FROM cells WHERE site_id = 'row_1'\"")
# A long text value is refused too.
geovor_cli_expect(cli.fields.shp_long_value_refused 3 STDERR "field 'note': 300 bytes, but a field of format ESRI Shapefile holds at most 254 bytes" SCRIPT
  "printf 'id,lat,lon,note\\na,0,0,%0300d\\nb,0,90,x\\nc,45,45,y\\n' 0 > ${fields_out}/long.csv && \"$0\" cells ${fields_out}/long.csv -o ${fields_out}/long.shp --overwrite -q")
# Field names cut to 10 characters are said, as GDAL says it.
geovor_cli_expect(cli.fields.shp_laundered_names_said 0 STDERR "laundered field name: 'circumradius_m' to 'circumradi'" SCRIPT
  "\"$0\" delaunay ${fixtures}/three_sites.csv -o ${fields_out}/tri.shp --overwrite -q")

# MapInfo has no Integer64: the counts go to Real (exact below 2^53), as ogr2ogr maps them.
geovor_cli_expect(cli.fields.mapinfo_works 0 SCRIPT
  "rm -f ${fields_out}/t.tab ${fields_out}/t.dat ${fields_out}/t.map ${fields_out}/t.id && \"$0\" cells ${typed} -o ${fields_out}/t.tab -q && ${has_fields} ${fields_out}/t.tab 'site_index: Real' 'big: Real' 'pop: Integer' 'elev: Real' 'founded: Date' 'updated: DateTime' && ogrinfo -ro -q ${fields_out}/t.tab -sql 'SELECT name FROM t WHERE site_index = 3' | grep -q 'name (String) = Delta'")
# Spreadsheets store no geometry: refused up front with the reason (exit 2), nothing written.
foreach(ext ods xlsx)
  geovor_cli_expect(cli.fields.${ext}_refused 2 STDERR "stores no geometry.*write CSV" SCRIPT
    "rm -f ${fields_out}/t.${ext} && \"$0\" cells ${typed} -o ${fields_out}/t.${ext} -q || ( test ! -e ${fields_out}/t.${ext} && exit 2 )")
endforeach()
# Formats that cannot hold geovor's layers are refused up front (exit 2), before the input is read
# (here a missing one, which would be exit 4) or anything created, with the reason and formats that
# work. From GDAL's metadata: no field of the writer's choosing (DXF, DGN, S57: neither
# DCAP_CREATE_FIELD nor DMD_CREATIONFIELDDATATYPES); from the documented list: GPX, GeoRSS, WAsP, ...
set(missing_input ${fields_out}/no_such_input.csv)
foreach(case "dxf;t.dxf;;format DXF holds no attribute fields of the writer's choosing \\(only its own schema\\), so every field would be lost. write GeoPackage, FlatGeobuf or GeoJSON"
              "dgn;t.dgn;;format DGN holds no attribute fields"
              "s57;t.000;-f S57;format S57 holds no attribute fields"
              "gpx;t.gpx;;format GPX holds points \\(waypoints\\) and lines \\(routes, tracks\\), no polygons. write GeoPackage"
              "georss;t.xml;-f GeoRSS;format GeoRSS holds only the elements of RSS .*--dsco USE_EXTENSIONS=YES"
              "wasp;t.map;-f WAsP;format WAsP cannot hold geovor's layers: a WAsP map holds lines of elevation or roughness only"
              "mvt;t.mvt;-f MVT;format MVT cannot hold geovor's layers: vector tiles snap coordinates"
              "vdv;t.x10;-f VDV;format VDV cannot hold geovor's layers: VDV-451 tables hold no geometry"
              "pcidsk;t.pix;;format PCIDSK cannot hold geovor's layers: it drops multi-part geometries"
              "pds4;t.xml;-f PDS4;format PDS4 cannot hold geovor's layers: it writes its tables into a directory")
  list(GET case 0 name)
  list(GET case 1 file)
  list(GET case 2 format)
  list(GET case 3 message)
  geovor_cli_expect(cli.fields.${name}_refused_up_front 2 STDERR "${message}" SCRIPT
    "rm -rf ${fields_out}/${file} && \"$0\" cells ${missing_input} -o ${fields_out}/${file} ${format} -q; s=$?; test ! -e ${fields_out}/${file} && exit $s")
endforeach()
# GPX holds lines (tracks) and points with geovor's fields as <extensions>: delaunay's edges
# written, GDAL reads them back; without the option refused before the input is read.
geovor_cli_expect(cli.fields.gpx_edges_refused_without_extensions 2 STDERR "format GPX holds only its own fields .*--dsco GPX_USE_EXTENSIONS=YES" SCRIPT
  "\"$0\" delaunay ${missing_input} --edges ${fields_out}/e.gpx --overwrite -q")
geovor_cli_expect(cli.fields.gpx_edges_with_extensions 0 STDOUT "ogr_edge_index \\(Integer\\) = 0" SCRIPT
  "rm -f ${fields_out}/ex.gpx && \"$0\" delaunay ${typed} --edges ${fields_out}/ex.gpx --dsco GPX_USE_EXTENSIONS=YES -q && ogrinfo -ro -q ${fields_out}/ex.gpx tracks")
geovor_cli_expect(cli.fields.nearest_selafin_refused_up_front 2 STDERR "format Selafin cannot hold geovor's layers: a Selafin \\(TELEMAC\\) mesh holds points with Real values only" SCRIPT
  "\"$0\" nearest --sites ${missing_input} --queries ${typed} -o ${fields_out}/n.slf -f Selafin --overwrite")
# --lco FID=NAME naming a field of geovor's: the fix is the option, not another format (the output
# is GeoPackage already).
geovor_cli_expect(cli.fields.lco_fid_on_a_field_says_the_fix 2 STDERR "format GPKG cannot hold the field 'site_id' \\(String\\) \\(GDAL: Wrong field type for site_id\\). --lco FID=site_id makes 'site_id' the layer's feature id column, which holds integer feature ids only: leave out that option or name another column \\(FID=fid is GPKG's default\\)\n$" SCRIPT
  "rm -f ${fields_out}/fid.gpkg && \"$0\" cells ${typed} -o ${fields_out}/fid.gpkg -q --lco FID=site_id")

# --field-type NAME=TYPE declares a column's type (GDAL's COLUMN_TYPES): over the typing by values
# (zip codes with leading zeros as Integer: 02134 -> 2134), the id column's String, and --all-text.
geovor_cli_expect(cli.fields.declared_types_gpkg 0 SCRIPT
  "rm -f ${fields_out}/ft.gpkg && \"$0\" cells ${typed} -o ${fields_out}/ft.gpkg -q --field-type zip=integer --field-type ID=Integer,pop=String && ${has_fields} ${fields_out}/ft.gpkg 'zip: Integer' 'id: Integer' 'pop: String' 'elev: Real' && ogrinfo -ro -q ${fields_out}/ft.gpkg -sql \"SELECT id, zip, pop, site_id FROM cells WHERE site_index = 0\" | tr '\\n' ' ' | grep -q 'id (Integer) = 1 *zip (Integer) = 2134 *pop (String) = 100 *site_id (String) = 001'")
geovor_cli_expect(cli.fields.declared_types_over_all_text 0 SCRIPT
  "rm -f ${fields_out}/fta.gpkg && \"$0\" cells ${typed} -o ${fields_out}/fta.gpkg -q --all-text --field-type pop=Integer64 --field-type founded=Date && ${has_fields} ${fields_out}/fta.gpkg 'pop: Integer64' 'founded: Date' 'elev: String' 'lat: String'")
# In GeoJSON a declared number is written as a number, a declared String quoted.
geovor_cli_expect(cli.fields.declared_types_geojson 0 SCRIPT
  "rm -f ${fields_out}/ft.geojson && \"$0\" cells ${typed} -o ${fields_out}/ft.geojson -q --field-type zip=Real,big=String && grep -qF '\"big\":\"1\",\"elev\":-3,\"founded\":\"1850-12-31\",\"updated\":\"2024-03-01T00:00:00Z\",\"zip\":90210,' ${fields_out}/ft.geojson && grep -qF '\"zip\":501,' ${fields_out}/ft.geojson")
# relax --sites-output carries them.
geovor_cli_expect(cli.fields.declared_types_sites_output 0 SCRIPT
  "rm -f ${fields_out}/ftc.gpkg ${fields_out}/fts.gpkg && \"$0\" relax ${typed} -o ${fields_out}/ftc.gpkg --sites-output ${fields_out}/fts.gpkg -n 1 -q --field-type zip=Integer && ${has_fields} ${fields_out}/fts.gpkg 'zip: Integer' && ${has_fields} ${fields_out}/ftc.gpkg 'zip: Integer'")
# A value that is not of its declared type is bad data (exit 3) naming the file, row, line, column,
# value and type; nothing is written.
geovor_cli_expect(cli.fields.declared_type_bad_value 3 STDERR "typed_columns.csv: row 1 \\(line 2\\), column 'name': 'Alpha' is not an Integer \\(declared Integer\\)" SCRIPT
  "rm -f ${fields_out}/ftb.gpkg && \"$0\" cells ${typed} -o ${fields_out}/ftb.gpkg -q --field-type name=Integer; s=$?; test ! -e ${fields_out}/ftb.gpkg && exit $s")
# With --overwrite, an old GeoJSON output is kept when a value is not of its declared type.
geovor_cli_expect(cli.fields.declared_type_bad_value_keeps_old_output 0 SCRIPT
  "echo old > ${fields_out}/ftk.geojson && ! \"$0\" cells ${typed} -o ${fields_out}/ftk.geojson --overwrite -q --field-type name=Real 2>/dev/null && grep -qx old ${fields_out}/ftk.geojson")
geovor_cli_expect(cli.fields.declared_type_needs_64_bits 3 STDERR "row 1 \\(line 2\\), column 'big': '5000000000' is not an Integer \\(declared Integer\\); it needs 64 bits: declare Integer64" SCRIPT
  "\"$0\" cells ${typed} -o ${fields_out}/ft64.geojson --overwrite -q --field-type big=Integer")
# An unknown column (with the nearest name) or type is a usage error (exit 2).
geovor_cli_expect(cli.fields.declared_type_unknown_column 2 STDERR "--field-type names 'popp', which is no column; did you mean 'pop'\\?" SCRIPT
  "\"$0\" cells ${typed} -o ${fields_out}/ftu.geojson --overwrite -q --field-type popp=Integer")
geovor_cli_expect(cli.fields.declared_type_unknown_type 2 STDERR "unknown type 'Int'; the types are String, Integer, Integer64, Real, Date, DateTime" SCRIPT
  "\"$0\" cells ${typed} -o ${fields_out}/ftt.geojson --overwrite -q --field-type pop=Int")
geovor_cli_expect(cli.fields.declared_type_malformed 2 STDERR "field type 'pop': expected NAME=TYPE" SCRIPT
  "\"$0\" delaunay ${typed} -o ${fields_out}/ftm.geojson --overwrite -q --field-type pop")
# OGR input: String always; other types from the values' text; a value that does not parse names
# the feature.
geovor_cli_expect(cli.fields.declared_types_ogr_input 0 SCRIPT
  "rm -f ${fields_out}/ftin.gpkg ${fields_out}/fto.fgb && cp ${typed} ${fields_out}/ftin.csv && echo String,String,Real,Real,Integer,Integer64,Real,Date,DateTime,String,String,Integer,String,Real > ${fields_out}/ftin.csvt && ogr2ogr -f GPKG ${fields_out}/ftin.gpkg ${fields_out}/ftin.csv -oo X_POSSIBLE_NAMES=lon -oo Y_POSSIBLE_NAMES=lat -select name,pop,elev,zip && \"$0\" cells ${fields_out}/ftin.gpkg -o ${fields_out}/fto.fgb -q --field-type pop=String,zip=Integer,elev=Real && ${has_fields} ${fields_out}/ftin.gpkg 'pop: Integer' 'zip: String' && ${has_fields} ${fields_out}/fto.fgb 'pop: String' 'zip: Integer' 'elev: Real' && ogrinfo -ro -q ${fields_out}/fto.fgb -sql \"SELECT zip FROM cells WHERE name = 'Delta'\" | grep -q 'zip (Integer) = 501'")
geovor_cli_expect(cli.fields.declared_type_ogr_bad_value 3 STDERR "ftbin.gpkg: feature 1, column 'elev': '12.5' is not an Integer \\(declared Integer\\)" SCRIPT
  "rm -f ${fields_out}/ftbin.gpkg && ogr2ogr -f GPKG ${fields_out}/ftbin.gpkg ${typed} -oo X_POSSIBLE_NAMES=lon -oo Y_POSSIBLE_NAMES=lat -oo AUTODETECT_TYPE=YES -select name,elev && \"$0\" cells ${fields_out}/ftbin.gpkg -o ${fields_out}/ftbo.geojson --overwrite -q --field-type elev=Integer")
# nearest --query-field-type: a query stream's columns typed in point outputs (a stream is not read
# ahead to detect types); an OGR query layer's over its own types; refused with CSV output (text).
set(query_csv_cmd "printf 'qid,lat,lon,zip,n\\na,10,20,02134,5\\nb,-5,3,00501,x\\n' >")
geovor_cli_expect(cli.fields.query_declared_types_stream 0 SCRIPT
  "${query_csv_cmd} ${fields_out}/q1.csv && rm -f ${fields_out}/q1.gpkg && \"$0\" nearest --sites ${typed} --queries ${fields_out}/q1.csv -o ${fields_out}/q1.gpkg --query-field-type zip=Integer -q && ${has_fields} ${fields_out}/q1.gpkg 'zip: Integer' 'n: String' 'qid: String' && ogrinfo -ro -q ${fields_out}/q1.gpkg -sql \"SELECT zip FROM nearest WHERE qid = 'b'\" | grep -q 'zip (Integer) = 501'")
geovor_cli_expect(cli.fields.query_declared_type_bad_value 3 STDERR "q2\\.csv: line 3, column 'n': 'x' is not an Integer \\(declared Integer\\)" SCRIPT
  "${query_csv_cmd} ${fields_out}/q2.csv && rm -f ${fields_out}/q2.gpkg && \"$0\" nearest --sites ${typed} --queries ${fields_out}/q2.csv -o ${fields_out}/q2.gpkg --query-field-type n=Integer --threads 2; s=$?; test ! -e ${fields_out}/q2.gpkg && exit $s")
geovor_cli_expect(cli.fields.query_declared_type_unknown_column 2 STDERR "--query-field-type names 'nn', which is no column of the queries. did you mean 'n'\\? \\(columns: qid, lat, lon, zip, n\\)" SCRIPT
  "${query_csv_cmd} ${fields_out}/q3.csv && \"$0\" nearest --sites ${typed} --queries ${fields_out}/q3.csv -o ${fields_out}/q3.gpkg --overwrite --query-field-type nn=Integer")
geovor_cli_expect(cli.fields.query_declared_types_not_with_csv_output 2 STDERR "--query-field-type types the query columns of point features .*geovor's CSV output has no types" SCRIPT
  "${query_csv_cmd} ${fields_out}/q4.csv && \"$0\" nearest --sites ${typed} --queries ${fields_out}/q4.csv -o ${fields_out}/q4.csv.out.csv --overwrite --query-field-type n=Integer")
geovor_cli_expect(cli.fields.query_declared_types_ogr_layer 0 SCRIPT
  "rm -f ${fields_out}/q5in.gpkg ${fields_out}/q5.fgb && ogr2ogr -f GPKG ${fields_out}/q5in.gpkg ${typed} -oo X_POSSIBLE_NAMES=lon -oo Y_POSSIBLE_NAMES=lat -oo AUTODETECT_TYPE=YES -select name,pop,elev && ${has_fields} ${fields_out}/q5in.gpkg 'pop: Integer' 'elev: Real' && \"$0\" nearest --sites ${typed} --queries ${fields_out}/q5in.gpkg -o ${fields_out}/q5.fgb --query-field-type pop=String,elev=String -q && ${has_fields} ${fields_out}/q5.fgb 'pop: String' 'elev: String' 'name: String'")
