// The options of a command's sites: they fill the library's SiteInput (geovor/layers/site_input.hpp),
// which reads, builds and accounts for the rows; its messages name these options.
#pragma once

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

#include "geovor/geo/site_reader.hpp"
#include "geovor/layers/site_input.hpp"

namespace geovor::tools {

/// The sites of a command (its -q sets `quiet`: no list of merged rows).
using SiteInputArgs = SiteInput;

/// Adds INPUT and the column options to a subcommand.
void add_site_input_options(CLI::App* cmd, SiteInputArgs& args);

/// Adds a repeatable option `name` NAME=TYPE[,NAME2=TYPE2] (parse_field_types) filling `out`; a
/// malformed one or an unknown type is a usage error.
CLI::Option* add_field_type_option(CLI::App* cmd, const std::string& name, std::vector<FieldTypeOverride>& out,
                                   const std::string& help);

/// Adds the options that say how to read a site table (columns, encoding, CRS); returns them.
std::vector<CLI::Option*> add_site_table_options(CLI::App* cmd, SiteInputArgs& args);

}  // namespace geovor::tools
