# Command-line conventions (issue 16): --version, a mistyped command named as such, `geovor help
# CMD`, -q on every command, the program's name in usage lines, numeric options checked.
set(conv_out ${CMAKE_CURRENT_BINARY_DIR}/conventions)
file(MAKE_DIRECTORY ${conv_out})

# The version is the project's (CMakeLists.txt, project(VERSION)).
geovor_cli_expect(cli.conventions.version 0 STDOUT "^geovor ${PROJECT_VERSION}\n$" COMMAND --version)
# A mistyped command is named, with the nearest command; a word near none lists them all.
geovor_cli_expect(cli.conventions.unknown_command 2 STDERR "^geovor: unknown command 'cels'; did you mean 'cells'\\?\n$"
  COMMAND cels ${fixtures}/three_sites.csv -o ${conv_out}/cels.geojson)
geovor_cli_expect(cli.conventions.unknown_command_prefix 2 STDERR "unknown command 'near'; did you mean 'nearest'\\?"
  COMMAND near --sites ${fixtures}/three_sites.csv)
geovor_cli_expect(cli.conventions.unknown_command_far 2
  STDERR "unknown command 'frobnicate'; the commands are info, cells, delaunay, relax, balance, index, nearest"
  COMMAND frobnicate)
# `geovor help CMD` is `geovor CMD --help`; `geovor help` is `geovor --help`.
geovor_cli_expect(cli.conventions.help_command 0 STDOUT "^Write the Voronoi cell[^\n]*\nUsage: geovor cells \\[OPTIONS\\] INPUT"
  COMMAND help cells)
geovor_cli_expect(cli.conventions.help_alone 0 STDOUT "Usage: geovor \\[OPTIONS\\] SUBCOMMAND" COMMAND help)
geovor_cli_expect(cli.conventions.help_unknown 2 STDERR "unknown command 'cels'; did you mean 'cells'" COMMAND help cels)
# Usage lines name the program, not the path it was run by (CTest runs it by its build path).
geovor_cli_expect(cli.conventions.program_name 0 STDOUT "\nUsage: geovor nearest \\[OPTIONS\\]" COMMAND nearest --help)
geovor_cli_expect(cli.conventions.program_name_in_errors 2 STDERR "^INPUT is required\nRun with --help" COMMAND cells)

# -q on every command: duplicates.csv has two merged rows and no rejected one, so a quiet run
# writes nothing on stderr (the merges stay in the counts on stdout).
geovor_cli_expect(cli.conventions.quiet.info 0 STDOUT "\nmerged: 2\n" STDERR "^$"
  COMMAND info ${fixtures}/duplicates.csv -q)
geovor_cli_expect(cli.conventions.quiet.index 0 STDOUT "\nmerged: 2\n" STDERR "^$"
  COMMAND index ${fixtures}/duplicates.csv -o ${conv_out}/duplicates.gvi --overwrite -q)
geovor_cli_expect(cli.conventions.quiet.nearest 0 STDOUT "^query_id,site_index,site_id,distance_m,id,lat_deg,lon_deg\n1,0,1,0," STDERR "^$"
  COMMAND nearest --sites ${fixtures}/duplicates.csv --queries ${fixtures}/duplicates.csv -q)
geovor_cli_expect(cli.conventions.quiet.cells 0 STDERR "^$"
  COMMAND cells ${fixtures}/duplicates.csv -o ${conv_out}/duplicates.geojson --overwrite -q)
geovor_cli_expect(cli.conventions.quiet.delaunay 0 STDERR "^$"
  COMMAND delaunay ${fixtures}/duplicates.csv -o ${conv_out}/duplicates_tri.geojson --overwrite -q)
geovor_cli_expect(cli.conventions.quiet.relax 0 STDERR "^$"
  COMMAND relax ${fixtures}/duplicates.csv -o ${conv_out}/duplicates_relax.geojson -n 1 --overwrite -q)
# Without -q the merges are listed (the tests above can fail).
geovor_cli_expect(cli.conventions.not_quiet.delaunay 0 STDERR "merged into the site of row"
  COMMAND delaunay ${fixtures}/duplicates.csv -o ${conv_out}/duplicates_tri_loud.geojson --overwrite)

# Numeric options: a negative, NaN, infinite or out-of-range value is a usage error (exit 2)
# naming the option. Before: `--k -1` was read as 2^64-1, NaN passed every range check.
set(three ${fixtures}/three_sites.csv)
set(numeric_cases
  "nearest_k_negative|--k|nearest --sites ${three} --queries ${three} --k -1"
  "nearest_k_zero|--k|nearest --sites ${three} --queries ${three} --k 0"
  "nearest_k_huge|--k|nearest --sites ${three} --queries ${three} --k 18446744073709551615"
  "nearest_threads_negative|--threads|nearest --sites ${three} --queries ${three} --threads -1"
  "nearest_merge_nan|--merge-m|nearest --sites ${three} --queries ${three} --merge-m nan"
  "cells_threads_negative|--threads|cells ${three} -o ${conv_out}/n.geojson --threads -1"
  "cells_densify_nan|--densify-m|cells ${three} -o ${conv_out}/n.geojson --densify-m nan"
  "cells_densify_inf|--densify-m|cells ${three} -o ${conv_out}/n.geojson --densify-m inf"
  "cells_densify_negative|--densify-m|cells ${three} -o ${conv_out}/n.geojson --densify-m -5"
  "cells_precision_zero|--precision|cells ${three} -o ${conv_out}/n.geojson --precision 0"
  "cells_merge_negative|--merge-m|cells ${three} -o ${conv_out}/n.geojson --merge-m -1"
  "delaunay_precision_18|--precision|delaunay ${three} -o ${conv_out}/n.geojson --precision 18"
  "delaunay_densify_text|--densify-m|delaunay ${three} -o ${conv_out}/n.geojson --densify-m 10m"
  "relax_iterations_negative|--iterations|relax ${three} -o ${conv_out}/n.geojson --iterations -1"
  "relax_tolerance_nan|--tolerance-m|relax ${three} -o ${conv_out}/n.geojson --tolerance-m nan"
  "relax_threads_negative|--threads|relax ${three} -o ${conv_out}/n.geojson --threads -3"
  "info_merge_nan|--merge-m|info ${three} --merge-m nan"
  "index_merge_inf|--merge-m|index ${three} -o ${conv_out}/n.gvi --merge-m inf"
  # --threads on every command (issue 36): one option, one check (tools/numeric_options.hpp).
  "info_threads_negative|--threads|info ${three} --threads -1"
  "info_threads_text|--threads|info ${three} --threads all"
  "delaunay_threads_negative|--threads|delaunay ${three} -o ${conv_out}/n.geojson --threads -1"
  "delaunay_threads_fraction|--threads|delaunay ${three} -o ${conv_out}/n.geojson --threads 1.5"
  "index_threads_negative|--threads|index ${three} -o ${conv_out}/n.gvi --threads -1"
  "index_threads_text|--threads|index ${three} -o ${conv_out}/n.gvi --threads two"
  "nearest_threads_text|--threads|nearest --sites ${three} --queries ${three} --threads 2x"
  "cells_threads_huge|--threads|cells ${three} -o ${conv_out}/n.geojson --threads 1000001"
  "relax_threads_exponent|--threads|relax ${three} -o ${conv_out}/n.geojson --threads 1e3"
  "balance_threads_negative|--threads|balance ${three} -o ${conv_out}/n.geojson --threads -1"
  "balance_threads_text|--threads|balance ${three} -o ${conv_out}/n.geojson --threads 0x10"
  "serve_threads_negative|--threads|serve ${three} --threads -1"
  "serve_threads_text|--threads|serve ${three} --threads 4.0")
foreach(case ${numeric_cases})
  string(REPLACE "|" ";" case "${case}")
  list(GET case 0 name)
  list(GET case 1 option)
  list(GET case 2 args)
  separate_arguments(args UNIX_COMMAND "${args}")
  geovor_cli_expect(cli.conventions.numeric.${name} 2 STDERR "^${option}: expected [^\n]*, got '" COMMAND ${args})
endforeach()

# --threads N on every command, 0 (one per core) by default: the same files, stdout and stderr
# for 1, 2, 3 and the default, on the weather stations and a generated hostile table
# (tests/cli/threads_test.py; serve's answers on threads: serve_test.py).
foreach(command info delaunay index nearest cells relax balance)
  add_test(NAME cli.conventions.threads.${command}
    COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/threads_test.py $<TARGET_FILE:geovor_cli> ${conv_out}/threads ${command}
    WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
  set_tests_properties(cli.conventions.threads.${command} PROPERTIES LABELS cli PASS_REGULAR_EXPRESSION "^ok\n$")
endforeach()

# geovor runs itself again with transparent huge pages for malloc (glibc.malloc.hugetlb=1 added to
# GLIBC_TUNABLES), keeping a hugetlb tunable the user set.
add_test(NAME cli.conventions.huge_pages
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/huge_pages.sh $<TARGET_FILE:geovor_cli> ${PROJECT_SOURCE_DIR}/${fixtures}/three_sites.csv
          ${conv_out}/huge_pages)

# scripts/geovor says that it is building, and where the log is, instead of minutes of silence on
# a fresh machine; silent when the command is up to date; a failed build shows its log (issue 34).
add_test(NAME cli.conventions.scripts_geovor_says_it_builds
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/scripts_geovor.sh ${PROJECT_SOURCE_DIR})
set_tests_properties(cli.conventions.scripts_geovor_says_it_builds PROPERTIES LABELS "cli" TIMEOUT 60)
