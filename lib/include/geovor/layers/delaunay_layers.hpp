/// \file delaunay_layers.hpp
/// \brief The Delaunay triangle layer (MultiPolygon features) and edge layer (MultiLineString
/// features) of a triangulation, written to any FeatureWriter (what `geovor delaunay` writes).
///
/// Triangle fields (triangle_layer_schema()): tri_index (Integer64), kind (String: proper, ghost or
/// great_circle, FaceKind), ghost (Integer64: 1 for a face outside the triangulation of the sites'
/// convex hull, DelaunayGeometry::is_outer), site_a/b/c (Integer64: site ids, counter-clockwise),
/// id_a/b/c (String: the ids of the rows the sites were built from), area_m2 (Real: WGS84
/// ellipsoid, of the polygon as written), area_sr (Real: sphere), circumradius_m (Real).
/// Edge fields (edge_layer_schema()): edge_index (Integer64: counts the edges written), site_a,
/// site_b (Integer64), id_a, id_b (String), length_m (Real: great circle on the sphere of radius
/// SiteEncoder::kEarthRadiusM), geodesic_m (Real: WGS84 geodesic between the two sites), hull
/// (Integer64: 1 for an edge of the boundary of the sites' convex hull), ghost (Integer64: 1 for an
/// edge between two outer faces).
/// Triangles are written in triangle id order, edges in the order of their first half-edge.
/// Geometry is at the precision of the DelaunayGeometry given: what collapses or cannot be
/// written valid gets an empty geometry and is reported, never dropped.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "geovor/delaunay/site_rows.hpp"
#include "geovor/geo/site_reader.hpp"
#include "geovor/io/feature_writer.hpp"
#include "geovor/lonlat/delaunay_geometry.hpp"

namespace geovor {

/// The fields of the triangle layer (the file comment).
std::vector<Field> triangle_layer_schema();
/// The fields of the edge layer (the file comment).
std::vector<Field> edge_layer_schema();

/// Options of write_triangle_layer() and write_edge_layer(); every default is documented.
struct DelaunayLayerOptions {
  /// Leave out the outer faces and edges (ghost = 1; there are some only when all sites lie in
  /// one hemisphere): the triangles written then tile the sites' convex hull. DEFAULT: false.
  bool no_ghosts = false;
  /// Called every 4,096 triangles (with the triangle id reached) or edges (with the edges
  /// written so far), on the calling thread. DEFAULT: none.
  std::function<void(std::size_t done)> progress;
};

/// A triangle written with an empty geometry, and why (it collapsed or would not be valid at
/// the output's precision).
struct UnwrittenTriangle {
  TriId triangle = kNoIndex;
  WrittenStatus status = WrittenStatus::Written;
};

/// What write_triangle_layer() wrote.
struct TriangleLayerReport {
  std::size_t triangles_written = 0;
  std::vector<UnwrittenTriangle> unwritten;  ///< by triangle id
};

/// What write_edge_layer() wrote.
struct EdgeLayerReport {
  std::size_t edges_written = 0;
  std::size_t collapsed = 0;  ///< edges written with an empty geometry: both ends one position
};

/// open_feature_writer(path, MultiPolygon, triangle_layer_schema(), options) (options.layer
/// is typically "triangles"). @exception Error as open_feature_writer().
std::unique_ptr<FeatureWriter> open_triangle_layer_writer(const std::string& path, const WriterOptions& options);
/// open_feature_writer(path, MultiLineString, edge_layer_schema(), options) (options.layer is
/// typically "edges"). @exception Error as open_feature_writer().
std::unique_ptr<FeatureWriter> open_edge_layer_writer(const std::string& path, const WriterOptions& options);

/// Writes the triangles of geometry.triangulation() (built from table's rows; `rows` is
/// rows_of_sites() of its build) to `writer`, opened with triangle_layer_schema(); does not
/// finish it. @exception Error as the writer.
TriangleLayerReport write_triangle_layer(FeatureWriter& writer, const SiteTable& table, const SiteRows& rows,
                                         const DelaunayGeometry& geometry, const DelaunayLayerOptions& options = {});

/// Writes the edges of geometry.triangulation() to `writer`, opened with edge_layer_schema(),
/// as write_triangle_layer() does. @exception Error as the writer.
EdgeLayerReport write_edge_layer(FeatureWriter& writer, const SiteTable& table, const SiteRows& rows,
                                 const DelaunayGeometry& geometry, const DelaunayLayerOptions& options = {});

/// Where write_delaunay_layers() writes (what `geovor delaunay` writes): the triangles and the
/// edges, each to a path ("" for none). The two paths may name one file of a format that holds
/// several layers (format_holds_layers(): GPKG, SQLite, ...): one data source with the two
/// layers, written with `triangles`'s options (creation options, update, overwrite) and
/// `edges.layer` as the edges' layer name.
struct DelaunayOutput {
  std::string triangles_path;
  WriterOptions triangles = triangles_defaults();  ///< DEFAULT: layer "triangles"
  std::string edges_path;
  WriterOptions edges = edges_defaults();  ///< DEFAULT: layer "edges"

  static WriterOptions triangles_defaults() {
    WriterOptions o;
    o.layer = "triangles";
    return o;
  }
  static WriterOptions edges_defaults() {
    WriterOptions o;
    o.layer = "edges";
    return o;
  }
};

/// What write_delaunay_layers() wrote.
struct DelaunayLayersReport {
  TriangleLayerReport triangles;
  EdgeLayerReport edges;
};

/// Whether `output` writes the triangles and the edges into one data source: both paths name
/// one file, and the edges' format is the triangles' or not given (the triangles' is used). @exception Error(InvalidArgument) as format_holds_layers() when
/// they do and the format is unknown.
bool one_data_source(const DelaunayOutput& output);

/// Writes the triangle layer and/or the edge layer of `geometry` (write_triangle_layer(),
/// write_edge_layer()); options.progress gets the triangles and edges written so far. Every
/// output is opened (an existing one refused) before the first feature is written and moved
/// into place once both layers are complete: a failure leaves no output.
/// @exception Error(InvalidArgument) when no path is given, or both paths name one file of a
///   format that holds one layer; otherwise as open_feature_writer() and the writers.
DelaunayLayersReport write_delaunay_layers(const DelaunayOutput& output, const SiteTable& table, const SiteRows& rows,
                                           const DelaunayGeometry& geometry, const DelaunayLayerOptions& options = {});

}  // namespace geovor
