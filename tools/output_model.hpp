// ogr2ogr's output model on the commands that write an OGR output (cells, delaunay, relax):
// -f/--format, --nln, --update, --overwrite, --lco, --dsco, passed to the library's WriterOptions.
#pragma once

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

#include "geovor/io/feature_writer.hpp"

namespace geovor::tools {

/// The output-model options of one command (its format and --overwrite are kept where the
/// command had them).
struct OutputModelArgs {
  std::string layer;  // --nln; "" for the command's default
  bool update = false;
  std::vector<std::string> layer_options, dataset_options;  // --lco, --dsco
};

/// Adds -f/--format (into `format`), --nln, --update, --overwrite (into `overwrite`), --lco and
/// --dsco to `cmd`; `default_layer` is the layer name without --nln, for the help.
void add_output_model_options(CLI::App* cmd, std::string& format, bool& overwrite, OutputModelArgs& model,
                              const std::string& default_layer);

/// Whether any of --nln, --update, --lco, --dsco was given (refused where geovor writes a CSV).
inline bool sets_gdal_options(const OutputModelArgs& model) {
  return model.update || !model.layer.empty() || !model.layer_options.empty() || !model.dataset_options.empty();
}

/// `options` with the model's layer name (unless empty), update and creation options.
void apply_output_model(const OutputModelArgs& model, WriterOptions& options);

}  // namespace geovor::tools
