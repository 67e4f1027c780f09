# CLI tests of `geovor balance` (issue 33; docs/weighted.md, "Balanced cells"): the bundled stations
# balanced, their sites' radii giving back the same cells through `geovor cells --weight-field`,
# capacities parsed per row, not converged (exit 4, nothing written), the options refused.
set(balance_out ${CMAKE_CURRENT_BINARY_DIR}/balance)
file(MAKE_DIRECTORY ${balance_out})
file(WRITE ${balance_out}/capacities.csv
  "name,lat,lon,capacity\nA,0,0,1\nB,0,90,2\nC,0,180,3\nD,0,-90,4\nE,60,45,1\nF,-60,-135,2\nG,45,-100,3\nH,-45,120,4\n"
  "I,10,10,\nJ,20,20,abc\nK,30,30,0\nL,40,40,-2\n")

geovor_cli_expect(cli.balance.stations 0 STDERR "rows 5634, sites 5631, merged 3, rejected 0; 5631 cells written"
  COMMAND balance datasets/weather_stations.csv -o ${balance_out}/stations.geojson --overwrite
          --sites-output ${balance_out}/stations_sites.csv)
# The radii written with --sites-output rebuild the very cells (same geometry, feature by feature).
geovor_cli_expect(cli.balance.sites_output_round_trip 0 SCRIPT
  "d=${balance_out}/rt && \"$0\" balance datasets/weather_stations.csv -o $d.balanced.geojson --sites-output $d.sites.csv --overwrite -q && \"$0\" cells $d.sites.csv --weight-field weight_m -o $d.cells.geojson --overwrite -q && grep -o '\"geometry\":.*' $d.balanced.geojson > $d.a && grep -o '\"geometry\":.*' $d.cells.geojson > $d.b && test $(wc -l < $d.a) -eq 5631 && test $(wc -l < $d.sites.csv) -eq 5632 && cmp $d.a $d.b && head -1 $d.sites.csv | grep -qx 'site_id,lat_deg,lon_deg,weight_m,target_m2'")
# Capacities: the bad rows are rejected with their reason, the others balanced; the cells carry weight_m.
geovor_cli_expect(cli.balance.capacities 0
  STDERR "row 9 [^\n]*rejected: capacity: empty.*row 10 [^\n]*rejected: capacity: \"abc\" is not a number.*row 11 [^\n]*rejected: capacity: capacity 0 is not positive.*row 12 [^\n]*rejected: capacity: capacity -2 is not positive.*rows 12, sites 8, merged 0, rejected 4; 8 cells written"
  COMMAND balance ${balance_out}/capacities.csv -o ${balance_out}/capacities.geojson --capacity-field capacity
          --tolerance 1e-9 --overwrite)
geovor_cli_expect(cli.balance.capacity_weight_m 0 STDOUT "\"weight_m\":0.0,\"name\":\"A\",\"lat\":0,\"lon\":0,\"capacity\":\"1\",\"target_m2\":25503281086204.4"
  SCRIPT "\"$0\" balance ${balance_out}/capacities.csv -o - --capacity-field capacity -q")
geovor_cli_expect(cli.balance.unknown_capacity_column 2 STDERR "no capacity column 'trucks'"
  COMMAND balance ${balance_out}/capacities.csv -o ${balance_out}/unknown.geojson --capacity-field trucks --overwrite)
# Not converged: exit 4 and no cells file.
geovor_cli_expect(cli.balance.not_converged 0 SCRIPT
  "f=${balance_out}/nc.geojson && rm -f $f && (\"$0\" balance datasets/weather_stations.csv -o $f --max-iterations 2 2> $f.err || test $? -eq 4) && ! test -e $f && grep -q 'not converged after 2 iterations' $f.err")
geovor_cli_expect(cli.balance.exit_4 4 STDERR "not converged"
  COMMAND balance datasets/weather_stations.csv -o ${balance_out}/nc2.geojson --max-iterations 1 --overwrite)
geovor_cli_expect(cli.balance.weight_field_refused 2 STDERR "weight-field"
  COMMAND balance ${balance_out}/capacities.csv -o ${balance_out}/w.geojson --weight-field capacity --overwrite)
geovor_cli_expect(cli.balance.bad_tolerance 2 STDERR "tolerance"
  COMMAND balance ${balance_out}/capacities.csv -o ${balance_out}/t.geojson --tolerance 0 --overwrite)
geovor_cli_expect(cli.help.balance 0 STDOUT "--capacity-field" COMMAND balance --help)
