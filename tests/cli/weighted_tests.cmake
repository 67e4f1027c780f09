# CLI tests of weighted sites (--weight-field, issue 33; docs/weighted.md): equal radii give the
# unweighted cells, hidden sites are listed and written empty, bad radii reject their rows.
set(weighted_out ${CMAKE_CURRENT_BINARY_DIR}/weighted)
file(MAKE_DIRECTORY ${weighted_out})

# Equal radii: the same features as without weights, but for weight_m (bundled stations and
# cities; the radius column is an input attribute in both runs).
foreach(data IN ITEMS stations cities)
  if(data STREQUAL stations)
    set(cat "cat datasets/weather_stations.csv")
  else()
    set(cat "gzip -dc datasets/geonames_cities.csv.gz")
  endif()
  geovor_cli_expect(cli.weighted.equal_radii_same_bytes_${data} 0 SCRIPT
    "d=${weighted_out}/eq_${data} && ${cat} | awk '{sub(/\\r$/,\"\")} NR==1{print $0\",radius_m\"} NR>1{print $0\",25000\"}' > $d.csv && \"$0\" cells $d.csv -o $d.plain.geojson --overwrite -q && \"$0\" cells $d.csv -o $d.weighted.geojson --weight-field radius_m --overwrite -q && grep -q '\"weight_m\":25000.0,' $d.weighted.geojson && sed 's/\"weight_m\":25000.0,//' $d.weighted.geojson > $d.stripped.geojson && cmp $d.plain.geojson $d.stripped.geojson")
endforeach()

# A site inside a large circle is hidden: listed on stderr and in --report, written empty, counted
# by info; exit 0.
geovor_cli_expect(cli.weighted.hidden_listed 0 STDERR "row 7 \\(id 'G', radius 0 m\\) is hidden.*row 1, id 'A'"
  COMMAND cells ${fixtures}/weighted_hidden.csv -o ${weighted_out}/hidden.geojson --weight-field radius_m --overwrite
          --report ${weighted_out}/hidden_report.csv)
geovor_cli_expect(cli.weighted.hidden_report 0 STDOUT "7,8,\"G\",hidden,6,\"power cell empty: site 0 holds its position\""
  SCRIPT "\"$0\" cells ${fixtures}/weighted_hidden.csv -o ${weighted_out}/hidden2.geojson --weight-field radius_m --overwrite -q --report ${weighted_out}/hidden_report2.csv && cat ${weighted_out}/hidden_report2.csv")
geovor_cli_expect(cli.weighted.hidden_empty_geometry 0
  STDOUT "\"site_id\":\"G\".*\"area_m2\":0.0,\"area_sr\":0.0,\"n_vertices\":0,\"neighbors\":\\[\\].*\"geometry\":\\{\"type\":\"MultiPolygon\",\"coordinates\":\\[\\]\\}"
  SCRIPT "\"$0\" cells ${fixtures}/weighted_hidden.csv -o - --weight-field radius_m -q | grep '\"id\":\"G\"'")
geovor_cli_expect(cli.weighted.info_hidden 0 STDOUT "sites: 6\nmerged: 0\nhidden: 1\n.*valid: yes"
  COMMAND info ${fixtures}/weighted_hidden.csv --weight-field radius_m)
geovor_cli_expect(cli.weighted.delaunay 0 STDERR "is hidden"
  COMMAND delaunay ${fixtures}/weighted_hidden.csv -o ${weighted_out}/hidden_tri.geojson --weight-field radius_m --overwrite)

# Bad radii reject their rows with the column named; the others are cells.
geovor_cli_expect(cli.weighted.bad_radii 0
  STDERR "row 2 [^\n]*rejected: radius_m: empty.*row 3 [^\n]*rejected: radius_m: \"abc\" is not a number.*row 4 [^\n]*rejected: radius_m: radius -1 m is outside.*row 5 [^\n]*rejected: radius_m: radius 10007558 m is outside.*row 8 [^\n]*rejected: radius_m: \"nan\" is not a number"
  COMMAND cells ${fixtures}/weighted_bad_radii.csv -o ${weighted_out}/bad.geojson --weight-field radius_m --overwrite)
geovor_cli_expect(cli.weighted.bad_radii_info 0 STDOUT "rows: 8\nsites: 3\nmerged: 0\nhidden: 0\nrejected: 5\n"
  COMMAND info ${fixtures}/weighted_bad_radii.csv --weight-field radius_m)
geovor_cli_expect(cli.weighted.unknown_column 2 STDERR "no weight column 'radius'"
  COMMAND cells ${fixtures}/weighted_bad_radii.csv -o ${weighted_out}/unknown.geojson --weight-field radius --overwrite)
geovor_cli_expect(cli.weighted.relax_refuses 2 STDERR "weight-field"
  COMMAND relax ${fixtures}/weighted_bad_radii.csv -o ${weighted_out}/relax.geojson -n 1 --weight-field radius_m --overwrite)

# An index of weighted sites (version 2): nearest answers the site whose power cell holds the
# query (--metric power, the default), never a hidden one; the sphere metric is refused; a table
# with --weight-field gives the same answers as its index. G at (0, 0.05) is hidden by A's 600 km
# circle; at (0, 45) A's power cos(45)/cos(600 km / R) beats B's cos(45); at (0, 50) B's wins.
geovor_cli_expect(cli.weighted.index_hidden 0 STDOUT "sites: 6\nmerged: 0\nrejected: 0\nhidden: 1\n" STDERR "id 'G'.*is hidden"
  COMMAND index ${fixtures}/weighted_hidden.csv --weight-field radius_m -o ${weighted_out}/hidden.gvi --overwrite)
geovor_cli_expect(cli.weighted.nearest_power 0 STDOUT "query_id,site_index,site_id,distance_m,lat,lon\n2,0,A,5559.75[0-9]*,0,0.05\n3,0,A,5003778.5[0-9]*,0,45\n4,1,B,4447803.1[0-9]*,0,50\n$"
  SCRIPT "\"$0\" index ${fixtures}/weighted_hidden.csv --weight-field radius_m -o ${weighted_out}/power.gvi --overwrite -q > /dev/null && printf 'lat,lon\\n0,0.05\\n0,45\\n0,50\\n' | \"$0\" nearest --sites ${weighted_out}/power.gvi")
geovor_cli_expect(cli.weighted.nearest_table_same 0
  SCRIPT "\"$0\" index ${fixtures}/weighted_hidden.csv --weight-field radius_m -o ${weighted_out}/same.gvi --overwrite -q > /dev/null && printf 'lat,lon\\n0,0.05\\n0,45\\n0,50\\n10,10\\n-89,3\\n' > ${weighted_out}/q.csv && \"$0\" nearest --sites ${weighted_out}/same.gvi --queries ${weighted_out}/q.csv --k 3 -o ${weighted_out}/a.csv --overwrite && \"$0\" nearest --sites ${fixtures}/weighted_hidden.csv --weight-field radius_m --queries ${weighted_out}/q.csv --k 3 --metric power -o ${weighted_out}/b.csv --overwrite -q && cmp ${weighted_out}/a.csv ${weighted_out}/b.csv")
geovor_cli_expect(cli.weighted.nearest_sphere_refused 2 STDERR "metric sphere: the sites are weighted, their metric is power"
  SCRIPT "\"$0\" index ${fixtures}/weighted_hidden.csv --weight-field radius_m -o ${weighted_out}/sphere.gvi --overwrite -q > /dev/null && printf 'lat,lon\\n0,0\\n' | \"$0\" nearest --sites ${weighted_out}/sphere.gvi --metric sphere -o ${weighted_out}/sphere.csv")
geovor_cli_expect(cli.weighted.nearest_weight_field_on_index 2 STDERR "--weight-field applies to a site table"
  SCRIPT "\"$0\" index ${fixtures}/weighted_hidden.csv --weight-field radius_m -o ${weighted_out}/twice.gvi --overwrite -q > /dev/null && printf 'lat,lon\\n0,0\\n' | \"$0\" nearest --sites ${weighted_out}/twice.gvi --weight-field radius_m")
