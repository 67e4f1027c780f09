# Row accounting over every CSV fixture (issue 16): check_fixture_accounting.py counts each file's
# data rows with Python's csv module and checks that `geovor cells --report`, `info` and `nearest`
# account for each exactly once (site, merged into a listed cell, or rejected with a reason), or
# that a file refused as a whole writes nothing. A new fixture is checked without being listed.
# Included by tests/cli/CMakeLists.txt.
file(GLOB accounting_fixtures CONFIGURE_DEPENDS
  ${PROJECT_SOURCE_DIR}/tests/cli/fixtures/*.csv ${PROJECT_SOURCE_DIR}/datasets/fixtures/*.csv)
list(SORT accounting_fixtures)
if(DEFINED GEOVOR_ORACLE_PYTHON)
  set(accounting_python ${GEOVOR_ORACLE_PYTHON})
else()
  set(accounting_python /usr/bin/python3)
endif()
add_test(NAME cli.accounting.fixtures
  COMMAND ${accounting_python} ${CMAKE_CURRENT_SOURCE_DIR}/check_fixture_accounting.py
          $<TARGET_FILE:geovor_cli> ${CMAKE_CURRENT_BINARY_DIR}/accounting ${accounting_fixtures}
          ${PROJECT_SOURCE_DIR}/datasets/weather_stations.csv
  WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
set_tests_properties(cli.accounting.fixtures PROPERTIES LABELS cli TIMEOUT 300
  PASS_REGULAR_EXPRESSION "accounting: [1-9][0-9]* files passed, 0 failed")
