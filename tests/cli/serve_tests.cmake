# geovor serve (issue 34): the server on a free loopback port against geovor nearest, concurrent
# requests, bad requests, /healthz and SIGTERM (tests/cli/serve_test.py, Python's standard library).
add_test(NAME cli.serve.nearest_and_errors
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/serve_test.py $<TARGET_FILE:geovor_cli>
          ${PROJECT_SOURCE_DIR}/datasets/weather_stations.csv ${CMAKE_CURRENT_BINARY_DIR}/serve)
set_tests_properties(cli.serve.nearest_and_errors PROPERTIES LABELS "cli" TIMEOUT 120)
# A port in use is a clear error, exit 4.
geovor_cli_expect(cli.serve.port_in_use 4 STDERR "127.0.0.1:[0-9]+: cannot listen there"
  SCRIPT "/usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/serve_port_in_use.py \"$0\" ${PROJECT_SOURCE_DIR}/${fixtures}/three_sites.csv")
# POST /nearest against geovor nearest, bad bodies (400, 413, 415), /metrics, reload under load
# (POST /admin/reload and SIGHUP) and a broken index kept out (tests/cli/serve_ops_test.py).
add_test(NAME cli.serve.join_metrics_reload
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/serve_ops_test.py $<TARGET_FILE:geovor_cli>
          ${PROJECT_SOURCE_DIR}/datasets/weather_stations.csv ${CMAKE_CURRENT_BINARY_DIR}/serve_ops)
set_tests_properties(cli.serve.join_metrics_reload PROPERTIES LABELS "cli" TIMEOUT 180)
# OGC API - Features over the sites and the cells of geovor cells, read back by GDAL's OAPIF
# driver (tests/cli/serve_features_test.py).
add_test(NAME cli.serve.ogc_api_features
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/serve_features_test.py $<TARGET_FILE:geovor_cli>
          ${PROJECT_SOURCE_DIR}/datasets/weather_stations.csv ${CMAKE_CURRENT_BINARY_DIR}/serve_features)
set_tests_properties(cli.serve.ogc_api_features PROPERTIES LABELS "cli" TIMEOUT 180)
# /map clicked in headless Chromium through Selenium (tests/cli/serve_map_test.py; skipped, 77,
# without chromium, chromium-driver or python3-selenium).
add_test(NAME cli.serve.map_in_chromium
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/serve_map_test.py $<TARGET_FILE:geovor_cli>
          ${PROJECT_SOURCE_DIR}/datasets/weather_stations.csv ${CMAKE_CURRENT_BINARY_DIR}/serve_map)
set_tests_properties(cli.serve.map_in_chromium PROPERTIES LABELS "cli" TIMEOUT 240 SKIP_RETURN_CODE 77)
# QGIS's OAPIF provider reads both layers (tests/cli/serve_qgis_test.py; skipped, 77, without
# python3-qgis).
add_test(NAME cli.serve.qgis_reads_layers
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/serve_qgis_test.py $<TARGET_FILE:geovor_cli>
          ${PROJECT_SOURCE_DIR}/datasets/weather_stations.csv ${CMAKE_CURRENT_BINARY_DIR}/serve_qgis)
set_tests_properties(cli.serve.qgis_reads_layers PROPERTIES LABELS "cli" TIMEOUT 180 SKIP_RETURN_CODE 77)
