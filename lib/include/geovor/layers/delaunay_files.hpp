/// \file delaunay_files.hpp
/// \brief The Delaunay layers (delaunay_layers.hpp) of a job's sites written to files, what
/// `geovor delaunay` does: one set of writer options for both outputs, checked before any work,
/// the geometry at the precision of the text outputs, progress on a terminal, and what could not
/// be written listed on a log.
#pragma once

#include <cstdio>
#include <string>

#include "geovor/delaunay/spherical_delaunay.hpp"
#include "geovor/geo/site_reader.hpp"
#include "geovor/io/feature_writer.hpp"
#include "geovor/layers/delaunay_layers.hpp"
#include "geovor/layers/site_input.hpp"

namespace geovor {

/// The outputs of the triangles and the edges (each path "" for none) that share `options` (format,
/// precision, overwrite, update, creation options; the triangles' layer is options.layer), the
/// edges with their own format ("": the extension's) and layer. Unless both go to one data source
/// (one_data_source()), the edges keep the creation options only where GDAL writes them
/// (output_kind()) and update only where their format holds several layers.
DelaunayOutput delaunay_output(const std::string& triangles_path, const std::string& edges_path,
                               const WriterOptions& options, const std::string& edges_format,
                               const std::string& edges_layer);

/// Refuses, before any work: two outputs that are one file (check_distinct_outputs(), naming them
/// `triangles_name` and `edges_name`), unless one data source of a format that holds both layers;
/// writer options an output cannot take (check_writer_options()).
/// @exception Error(InvalidArgument) as those.
void check_delaunay_output(const DelaunayOutput& output, const std::string& triangles_name = "triangles_path",
                           const std::string& edges_name = "edges_path");

/// Options of write_delaunay_files(); every default is documented.
struct DelaunayFilesOptions {
  /// DelaunayGeometryOptions::densify_m. DEFAULT: 100.
  double densify_m = 100;
  /// DelaunayLayerOptions::no_ghosts. DEFAULT: false.
  bool no_ghosts = false;
  /// Where what could not be written is listed (and the progress printed when it is a terminal);
  /// null: nowhere. DEFAULT: stderr.
  std::FILE* log = stderr;
  /// No progress, no summary (delaunay_to_files()). DEFAULT: false.
  bool quiet = false;
  /// What the caller's users call WriterOptions::precision, in messages (the geovor command:
  /// --precision). DEFAULT: "precision".
  std::string precision_name = "precision";
};

/// Writes the layers of `dt` (built from `table`'s sites with `report`) to `output`
/// (write_delaunay_layers()). The positions are computed as the text outputs (GeoJSON,
/// GeoJSONSeq) write them, at output.triangles.precision, when there is one (a binary output
/// beside it gets the same rounded positions, as doubles); else at full precision. Lists on the
/// log, even when quiet, at most 20 triangles written with an empty geometry, and the number of
/// edges whose ends are one position.
/// @exception Error as write_delaunay_layers().
DelaunayLayersReport write_delaunay_files(const DelaunayOutput& output, const SiteTable& table, const BuildReport& report,
                                          const SphericalDelaunay& dt, const DelaunayFilesOptions& options = {});

/// Reads `input`'s sites (read_site_input()), builds them (weighted sites with their radii),
/// lists the build on the log (list_build(): the merged rows unless input.quiet, the hidden sites,
/// which are no vertex of any triangle, always) and writes their layers (write_delaunay_files());
/// unless options.quiet, says the counts on options.log: "SOURCE: rows N, sites S, merged M,
/// rejected R; triangles T (ghost G), W written to PATH; edges E written to PATH".
/// @exception Error as read_site_input(), the build and write_delaunay_files().
DelaunayLayersReport delaunay_to_files(const SiteInput& input, const DelaunayOutput& output,
                                       const DelaunayFilesOptions& options = {});

}  // namespace geovor
