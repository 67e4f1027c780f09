# CLI tests of input rules that tests/oracle/input_oracle.py found broken (issue 16), each failing
# before its fix. Included by tests/cli/CMakeLists.txt.
set(input_rules_dir ${CMAKE_CURRENT_BINARY_DIR}/input_rules)
file(MAKE_DIRECTORY ${input_rules_dir})

# A UTF-16 file without an extension, with --encoding UTF-16: its head, decoded, is delimited text
# (was: its NUL bytes sent it to GDAL, "not recognized as a supported file format").
geovor_cli_expect(cli.input_rules.utf16_no_extension 0 STDOUT "\nrows: 3\nsites: 3\nmerged: 0\nrejected: 0\n"
  SCRIPT "printf 'id\\073lat\\073lon\\nZ\\374rich\\07347,37\\0738,54\\nb\\07310\\07310\\nc\\0735\\0733\\n' | iconv -f ISO-8859-1 -t UTF-16 > ${input_rules_dir}/utf16_stations && \"$0\" info ${input_rules_dir}/utf16_stations --encoding UTF-16")
# The same without --encoding is not text: GDAL's (its message), never read as garbled text.
geovor_cli_expect(cli.input_rules.utf16_unsaid 3 STDERR "utf16_unsaid: not a vector data source GDAL can read"
  SCRIPT "printf 'id\\073lat\\073lon\\nb\\07310\\07310\\n' | iconv -f ISO-8859-1 -t UTF-16 > ${input_rules_dir}/utf16_unsaid && \"$0\" info ${input_rules_dir}/utf16_unsaid")
