# CLI tests of inputs that can be read only once (issue 16): a FIFO (as a shell's process
# substitution gives, /dev/fd/N), /dev/stdin and `-` are read as delimited text, opened once (a
# second open of a FIFO would wait for a writer forever); a stream that is not delimited text is
# refused with exit 3, naming it and saying what to do, never a GDAL error. Each test has its own
# FIFO; the writer is killed if geovor never opened it. Included by tests/cli/CMakeLists.txt.
set(stream_dir ${CMAKE_CURRENT_BINARY_DIR}/stream_input)
file(MAKE_DIRECTORY ${stream_dir})
set(stream_rows "id,lat,lon\\na,0,0\\nb,10,10\\nc,5,3\\n")

# geovor_stream_test(name exit_code fifo_text STDOUT regex STDERR regex COMMAND text FIFO_NAME name):
# runs `sh -c` (commands on separate lines: a ';' would split the CMake list) with a FIFO
# (named FIFO_NAME, default fifo) written `fifo_text` in the background; `$G` is geovor, `$F` the
# FIFO, `$D` the test's folder.
function(geovor_stream_test name exit_code text)
  cmake_parse_arguments(ARG "" "STDOUT;STDERR;COMMAND;FIFO_NAME" "" ${ARGN})
  if(NOT DEFINED ARG_FIFO_NAME)
    set(ARG_FIFO_NAME fifo)
  endif()
  set(d ${stream_dir}/${name})
  file(MAKE_DIRECTORY ${d})
  set(args)
  if(DEFINED ARG_STDOUT)
    list(APPEND args STDOUT "${ARG_STDOUT}")
  endif()
  if(DEFINED ARG_STDERR)
    list(APPEND args STDERR "${ARG_STDERR}")
  endif()
  geovor_cli_expect(cli.stream.${name} ${exit_code} ${args} SCRIPT
    "G=\"$0\" D=${d} F=${d}/${ARG_FIFO_NAME}\nrm -f $F && mkfifo $F || exit 99\nprintf '${text}' > $F 2>/dev/null & w=$!\n${ARG_COMMAND}\nrc=$?\nkill $w 2>/dev/null\nexit $rc")
  set_tests_properties(cli.stream.${name} PROPERTIES TIMEOUT 30)
endfunction()

# A FIFO without an extension: read once as CSV (was: handed to GDAL, which opened it twice and waited).
geovor_stream_test(fifo_info 0 "${stream_rows}" STDOUT "\nrows: 3\nsites: 3\nmerged: 0\nrejected: 0\n"
  COMMAND "$G info $F")
# Through geovor-gdal (GeoPackage output): the FIFO is still read once; GDAL reads back 3 cells.
geovor_stream_test(fifo_cells_gpkg 0 "${stream_rows}" STDOUT "Feature Count: 3\n"
  COMMAND "$G cells $F -o $D/cells.gpkg --overwrite -q && ogrinfo -so $D/cells.gpkg cells")
# Sites and queries from FIFOs (nearest looks for an index header only in regular files).
geovor_stream_test(fifo_nearest 0 "${stream_rows}" STDOUT "^query_id,site_index,site_id,distance_m,src_query_id,lat,lon\nq1,1,b,0,q1,10,10\n$"
  COMMAND "printf 'query_id,lat,lon\\nq1,10,10\\n' | $G nearest --sites $F --queries /dev/stdin")
# /dev/stdin and `-` (a pipe).
geovor_cli_expect(cli.stream.dev_stdin 0 STDOUT "\nrows: 3\nsites: 3\n"
  SCRIPT "printf '${stream_rows}' | \"$0\" info /dev/stdin")
geovor_cli_expect(cli.stream.dash 0 STDOUT "\nrows: 3\nsites: 3\n"
  SCRIPT "printf '${stream_rows}' | \"$0\" info -")
# Not delimited text from a stream: exit 3, the file named, the reason and what to do.
geovor_stream_test(fifo_json 3 "{\"type\": \"FeatureCollection\", \"features\": []}\\n"
  STDERR "stream_input/fifo_json/fifo: not delimited text: it starts with '{' \\(JSON\\?\\); a pipe, FIFO, device or standard input is read as delimited text only \\(GDAL needs a file it can reopen\\): save the data to a file and give that"
  COMMAND "$G info $F")
geovor_cli_expect(cli.stream.stdin_binary 3
  STDERR "<stdin>: not delimited text: a NUL byte in its first 4 KiB"
  SCRIPT "printf 'GPKG\\000\\001\\002' | \"$0\" cells - -o - -q")
# A FIFO named .geojson is still a stream (GDAL would open it twice): read as text, refused as JSON.
# (Created under that name: renaming it raced the writer's open, which then made a regular file
# of the old name while geovor waited on the FIFO for a writer: a 30 s timeout, once.)
geovor_stream_test(fifo_geojson_name 3 "{\"type\": \"FeatureCollection\"}\\n" FIFO_NAME x.geojson
  STDERR "not delimited text: it starts with '{'"
  COMMAND "$G info $F")
