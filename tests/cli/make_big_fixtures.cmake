# Writes the robustness fixtures too big to check in (tests/cli/robustness_tests.cmake):
#
#   cmake -DDIR=<dir> -P make_big_fixtures.cmake
#
#  - identical_1e6.csv: 10^6 rows at one position (45.5, -73.5), no id column;
#  - long_lines.csv: rows 1 and 4 plain; row 2 a 10 MB name (accepted); row 3 a 10 MB field and
#    nothing else (2 fields of 4: rejected); row 5 a 10 MB number as latitude (out of the range of
#    a double: rejected);
#  - long_query_lines.csv: queries, line 3 a 10 MB number, line 4 10 MB of letters, lines 2 and 5
#    plain;
#  - queries_crlf_bom.csv: a UTF-8 byte order mark, CRLF line ends, an empty line, no final line end.
cmake_minimum_required(VERSION 3.25)
file(MAKE_DIRECTORY ${DIR})
string(REPEAT "45.5,-73.5\n" 1000000 rows)
file(WRITE ${DIR}/identical_1e6.csv "lat,lon\n${rows}")
set(rows)
string(REPEAT "x" 10000000 ten_mb)
string(REPEAT "9" 10000000 ten_mb_digits)
file(WRITE ${DIR}/long_lines.csv
  "id,name,lat,lon\n1,a,10,20\n2,${ten_mb},30,40\n3,${ten_mb}\n4,b,-10,-20\n5,c,${ten_mb_digits},5\n")
file(WRITE ${DIR}/long_query_lines.csv "lat,lon\n10,20\n${ten_mb_digits},5\n${ten_mb}\n30,40\n")
string(ASCII 239 187 191 bom)
file(WRITE ${DIR}/queries_crlf_bom.csv "${bom}id,lat,lon\r\nq1,10,20\r\n\r\nq2,-10,30")
