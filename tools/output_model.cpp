#include "output_model.hpp"

namespace geovor::tools {
namespace {

// NAME=VALUE, as GDAL's creation options are written.
CLI::Validator name_value() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        const std::size_t eq = text.find('=');
        if (eq == std::string::npos || eq == 0) return "expected NAME=VALUE, got '" + text + "'";
        return "";
      },
      "NAME=VALUE");
}

}  // namespace

void add_output_model_options(CLI::App* cmd, std::string& format, bool& overwrite, OutputModelArgs& model,
                              const std::string& default_layer) {
  cmd->add_option("-f,--format", format,
                  "OGR driver name, overriding the extension (GeoJSON, GeoJSONSeq, GPKG, FlatGeobuf, \"ESRI Shapefile\", CSV, ...); "
                  "one that cannot hold the layer (ODS, DXF, GPX polygons, ...) is refused before any work, with the reason");
  cmd->add_option("--nln", model.layer, "Layer name (default " + default_layer + ")");
  cmd->add_flag("--update", model.update,
                "Add the layer to an existing data source of a format that holds several (GPKG, SQLite, ...), its other "
                "layers untouched; a layer of the same name needs --overwrite");
  cmd->add_flag("--overwrite", overwrite,
                "Replace existing outputs: in a data source that holds several layers (GPKG, ...), only the named layer, "
                "the others kept; otherwise the file");
  cmd->add_option("--lco", model.layer_options, "GDAL layer creation option NAME=VALUE (as ogr2ogr -lco), repeatable")
      ->allow_extra_args(false)
      ->check(name_value());
  cmd->add_option("--dsco", model.dataset_options,
                  "GDAL dataset creation option NAME=VALUE (as ogr2ogr -dsco) for a new data source, repeatable")
      ->allow_extra_args(false)
      ->check(name_value());
}

void apply_output_model(const OutputModelArgs& model, WriterOptions& options) {
  if (!model.layer.empty()) options.layer = model.layer;
  options.update = model.update;
  options.layer_options = model.layer_options;
  options.dataset_options = model.dataset_options;
}

}  // namespace geovor::tools
