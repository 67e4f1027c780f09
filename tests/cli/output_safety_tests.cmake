# Output safety (issue 15): every file geovor writes goes through one primitive
# (lib/include/geovor/core/output_target.hpp). Each test below failed before it.
set(safe_out ${CMAKE_CURRENT_BINARY_DIR}/safe_outputs)
file(MAKE_DIRECTORY ${safe_out} ${safe_out}/sub)
set(safe_fixtures ${PROJECT_SOURCE_DIR}/datasets/fixtures)

# 1. Two outputs of one command that are the same file are refused before any work (exit 2,
# both options named), and nothing is written: the same path, an alias (./X, sub/../X), a hard
# link, a symbolic link, `-` twice. Before: exit 0 and one output silently lost.
set(same_file_message "--output [^\n]* and --(report|edges|sites-output) [^\n]* are the same file")
geovor_cli_expect(cli.outputs.same_file.report 2 STDERR "${same_file_message}" SCRIPT
  "rm -f ${safe_out}/same.csv && \"$0\" cells ${safe_fixtures}/three_sites.csv -o ${safe_out}/same.csv --report ${safe_out}/same.csv -q\nrc=$?\ntest ! -e ${safe_out}/same.csv || exit 99\nexit $rc")
geovor_cli_expect(cli.outputs.same_file.delaunay_overwrite 2 STDERR "${same_file_message}" SCRIPT
  "printf keep > ${safe_out}/tri.geojson && \"$0\" delaunay ${safe_fixtures}/three_sites.csv -o ${safe_out}/tri.geojson --edges ${safe_out}/tri.geojson --overwrite -q\nrc=$?\ntest \"$(cat ${safe_out}/tri.geojson)\" = keep || exit 99\nexit $rc")
geovor_cli_expect(cli.outputs.same_file.relax_dot_alias 2 STDERR "${same_file_message}" SCRIPT
  "cd ${safe_out} && rm -f relax.geojson && \"$0\" relax ${safe_fixtures}/cube_corners.csv -o relax.geojson --sites-output ./relax.geojson -n 1 -q\nrc=$?\ntest ! -e relax.geojson || exit 99\nexit $rc")
geovor_cli_expect(cli.outputs.same_file.dotdot_alias 2 STDERR "${same_file_message}"
  COMMAND delaunay ${safe_fixtures}/three_sites.csv -o ${safe_out}/dotdot.geojson --edges ${safe_out}/sub/../dotdot.geojson -q)
geovor_cli_expect(cli.outputs.same_file.hard_link 2 STDERR "${same_file_message}" SCRIPT
  "printf keep > ${safe_out}/linked.csv && ln -f ${safe_out}/linked.csv ${safe_out}/hard.csv && \"$0\" cells ${safe_fixtures}/three_sites.csv -o ${safe_out}/linked.csv --report ${safe_out}/hard.csv --overwrite -q\nrc=$?\ntest \"$(cat ${safe_out}/linked.csv)\" = keep || exit 99\nexit $rc")
geovor_cli_expect(cli.outputs.same_file.symlink 2 STDERR "${same_file_message}" SCRIPT
  "printf keep > ${safe_out}/target.geojson && ln -sf target.geojson ${safe_out}/soft.geojson && \"$0\" relax ${safe_fixtures}/cube_corners.csv -o ${safe_out}/soft.geojson --sites-output ${safe_out}/target.geojson -n 1 --overwrite -q\nrc=$?\ntest \"$(cat ${safe_out}/target.geojson)\" = keep || exit 99\nexit $rc")
geovor_cli_expect(cli.outputs.same_file.stdout_twice 2 STDOUT "^$" STDERR "--output - and --report - are the same file"
  COMMAND cells ${safe_fixtures}/three_sites.csv -o - --report - -q)
# Devices are written in place: /dev/null may take two outputs.
geovor_cli_expect(cli.outputs.dev_null_twice 0
  COMMAND delaunay ${safe_fixtures}/three_sites.csv -o /dev/null --edges /dev/null --format GeoJSON --edges-format GeoJSON -q)

# 2. A file that appears at the target while geovor runs is not replaced without --overwrite
# (exit 4, the file named and intact). Before: replaced, exit 0.
add_test(NAME cli.outputs.no_clobber_race
  COMMAND ${CMAKE_COMMAND} -DEXPECT_EXIT=4 "-DSTDERR_REGEX=out\\.csv: exists; use --overwrite to replace it"
          -P ${expect_exit} -- sh ${CMAKE_CURRENT_SOURCE_DIR}/output_safety.sh race $<TARGET_FILE:geovor_cli>
          ${safe_out}/race ${safe_fixtures}/three_sites.csv)

# 3. SIGTERM, SIGINT and SIGHUP remove the temporaries (exit 143, 130, 129). Before: a hidden
# `.out.csv.tmp-PID-0` was left behind.
foreach(pair "TERM|143" "INT|130" "HUP|129" "report_TERM|143")
  string(REPLACE "|" ";" pair "${pair}")
  list(GET pair 0 sig)
  list(GET pair 1 code)
  add_test(NAME cli.outputs.signal.${sig}
    COMMAND ${CMAKE_COMMAND} -DEXPECT_EXIT=${code} -P ${expect_exit} --
            sh ${CMAKE_CURRENT_SOURCE_DIR}/output_safety.sh ${sig} $<TARGET_FILE:geovor_cli>
            ${safe_out}/signal_${sig} ${safe_fixtures}/three_sites.csv)
endforeach()

# 4. Output names of 250 bytes (the limit is 255): the temporaries' names are short. Before:
# "File name too long" for the temporary.
string(REPEAT "n" 242 long_stem)  # + a 4- to 8-byte extension: 246 to 250 bytes
geovor_cli_expect(cli.outputs.long_name.cells 0 SCRIPT
  "\"$0\" cells ${safe_fixtures}/three_sites.csv -o ${safe_out}/${long_stem}.geojson --report ${safe_out}/${long_stem}.csvrep --overwrite -q && test -s ${safe_out}/${long_stem}.geojson && test -s ${safe_out}/${long_stem}.csvrep")
geovor_cli_expect(cli.outputs.long_name.nearest 0 SCRIPT
  "\"$0\" nearest --sites ${safe_fixtures}/three_sites.csv --queries ${safe_fixtures}/three_sites.csv -o ${safe_out}/${long_stem}nnnn.csv --overwrite && test -s ${safe_out}/${long_stem}nnnn.csv")
geovor_cli_expect(cli.outputs.long_name.index 0 SCRIPT
  "\"$0\" index ${safe_fixtures}/three_sites.csv -o ${safe_out}/${long_stem}.gvi00 --overwrite && test -s ${safe_out}/${long_stem}.gvi00")
geovor_cli_expect(cli.outputs.long_name.flatgeobuf 0 SCRIPT
  "\"$0\" cells ${safe_fixtures}/three_sites.csv -o ${safe_out}/${long_stem}nnnn.fgb --overwrite -q && test -s ${safe_out}/${long_stem}nnnn.fgb")
set_tests_properties(cli.outputs.no_clobber_race PROPERTIES LABELS cli TIMEOUT 60)
foreach(sig TERM INT HUP report_TERM)
  set_tests_properties(cli.outputs.signal.${sig} PROPERTIES LABELS cli TIMEOUT 60)
endforeach()
