#include "site_input.hpp"

#include "geovor/core/error.hpp"
#include "geovor/geo/column_types.hpp"
#include "numeric_options.hpp"

namespace geovor::tools {
namespace {

// "X,Y,Z" into its names ("" gives none).
void split_names(const std::string& text, std::vector<std::string>& names) {
  if (text.empty()) return;
  names.clear();
  std::string name;
  for (const char c : text + ",") {
    if (c != ',') {
      name += c;
    } else {
      names.push_back(name);
      name.clear();
    }
  }
}

}  // namespace

void add_site_input_options(CLI::App* cmd, SiteInputArgs& args) {
  cmd->add_option("INPUT", args.input,
                  "Sites: CSV with a header (- for stdin; a pipe or FIFO is read as CSV) or any OGR point layer (GeoPackage, Shapefile, GeoJSON, FlatGeobuf)")
      ->required();
  add_site_table_options(cmd, args);
  cmd->add_option("--layer", args.layer, "Layer of a multi-layer OGR input (GeoPackage, ...); not for CSV");
  cmd->add_flag("--all-text", [&args](std::int64_t) { args.reader.detect_types = false; },
               "Keep every input column as text (String), as read; by default CSV columns are typed by their values "
               "(Integer, Integer64, Real, Date, DateTime) and OGR fields keep their types");
  add_field_type_option(cmd, "--field-type", args.reader.field_types,
                        "Declare an input column's type, over the typing by values, --all-text and the id rule: "
                        "NAME=TYPE (String, Integer, Integer64, Real, Date, DateTime; case-insensitive), repeatable or "
                        "NAME=TYPE,NAME2=TYPE2 (GDAL's COLUMN_TYPES); a value not of that type is bad data (exit 3)");
  cmd->add_option("--weight-field", args.weight_field,
                  "Weighted sites: the column holding each site's radius in metres (0 <= r < 10,007,557, a quarter "
                  "of the circumference); the cells are then power cells (docs/weighted.md). A row whose radius is "
                  "empty, not a number or out of range is rejected");
  cmd->add_option("--merge-m", args.merge_m,
                  "Merge sites closer than this many metres (default and minimum: 2^-24 R = 0.38 m)")
      ->check(finite_above(0, true));
}

CLI::Option* add_field_type_option(CLI::App* cmd, const std::string& name, std::vector<FieldTypeOverride>& out,
                                   const std::string& help) {
  return cmd
      ->add_option_function<std::vector<std::string>>(
          name,
          [&out, name](const std::vector<std::string>& specs) {
            out.clear();
            try {
              for (const std::string& spec : specs) parse_field_types(spec, out);
            } catch (const Error& e) {
              throw CLI::ValidationError(name, e.what());
            }
          },
          help)
      ->type_name("NAME=TYPE")
      ->allow_extra_args(false);
}

std::vector<CLI::Option*> add_site_table_options(CLI::App* cmd, SiteInputArgs& args) {
  args.layer_name = "--layer";  // the library's messages name the options by these
  args.id_field_name = "--id-field";
  return {
      cmd->add_option("--lat-field", args.reader.lat_field,
                      "Latitude (or y) column (default: found by name, case-insensitive: lat, Latitude (deg), "
                      "stop_lat, decimalLatitude, latitude_deg, POINT_Y, y...; several equally good ones are refused)"),
      cmd->add_option("--lon-field", args.reader.lon_field,
                      "Longitude (or x) column (default: found by name: lon, lng, long, Longitude, stop_lon, "
                      "decimalLongitude, longitude_deg, POINT_X, x...)"),
      cmd->add_option("--id-field", args.reader.id_field,
                      "Identifier column (default: id, icao, code or name; else the row number); '#row': the row number"),
      cmd->add_option_function<std::string>("--ecef-fields", [&args](const std::string& names) { split_names(names, args.reader.ecef_fields); },
                                            "X,Y,Z columns of ECEF metres instead of latitude/longitude"),
      cmd->add_option("--encoding", args.reader.encoding,
                      "Encoding of a CSV input that is not UTF-8 (ISO-8859-1, CP1252, UTF-16...; iconv's names)"),
      cmd->add_option("--s-srs", args.reader.s_srs,
                      "Coordinate system of the input's coordinates (EPSG:2154, a WKT, a PROJ string): CSV x/y "
                      "columns are transformed to WGS84 (rows outside its area of use rejected); replaces an OGR layer's own"),
  };
}

}  // namespace geovor::tools
