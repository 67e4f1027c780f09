# geovor serve (issue 34): the server on a free loopback port against geovor nearest, concurrent
# requests, bad requests, /healthz and SIGTERM (tests/cli/serve_test.py, Python's standard library).
add_test(NAME cli.serve.nearest_and_errors
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/serve_test.py $<TARGET_FILE:geovor_cli>
          ${PROJECT_SOURCE_DIR}/datasets/weather_stations.csv ${CMAKE_CURRENT_BINARY_DIR}/serve)
set_tests_properties(cli.serve.nearest_and_errors PROPERTIES LABELS "cli" TIMEOUT 120)
# A port in use is a clear error, exit 4.
geovor_cli_expect(cli.serve.port_in_use 4 STDERR "127.0.0.1:[0-9]+: cannot listen there"
  SCRIPT "/usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/serve_port_in_use.py \"$0\" ${PROJECT_SOURCE_DIR}/${fixtures}/three_sites.csv")
