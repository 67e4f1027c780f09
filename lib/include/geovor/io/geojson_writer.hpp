/// \file geojson_writer.hpp
/// \brief The native GeoJSON (RFC 7946) and GeoJSON text sequence (RFC 8142) writer. Its pieces
/// are headers of their own, included here: bounding boxes (bbox.hpp), the geometry check
/// (geometry_check.hpp), numbers (number_format.hpp) and JSON text (json_text.hpp).
///
/// Output layout (stable, so it can be diffed and processed line by line):
/// - FeatureCollection: `{"type":"FeatureCollection","name":LAYER,"features":[` LF, one feature
///   per line separated by `,` LF, then `],"bbox":[w,s,e,n]}` LF. The collection bbox comes last
///   because the writer streams; JSON member order carries no meaning. "name" is the layer name
///   (a foreign member, as GDAL writes it). No "crs" member (RFC 7946 §4).
/// - Feature: `{"type":"Feature","id":ID,"bbox":[w,s,e,n],"properties":{...},"geometry":{...}}`;
///   "id" only when WriterOptions::id_field is set and its value is not null. Unlike GDAL's
///   ID_FIELD, the id field also stays in "properties", so every output format carries the same
///   attributes.
/// - Sequence (RFC 8142): each feature is one record `RS JSON LF` (RS = 0x1E) when the path ends
///   in ".geojsons"; otherwise (".geojsonl", any other name, stdout) newline-delimited `JSON LF`,
///   GDAL's GeoJSONSeq default. A sequence has no collection and no collection bbox.
#pragma once

#include <functional>
#include <memory>
#include <string_view>
#include <string>
#include <vector>

#include "geovor/io/bbox.hpp"
#include "geovor/io/feature_writer.hpp"
#include "geovor/io/geometry_check.hpp"
#include "geovor/io/json_text.hpp"
#include "geovor/io/number_format.hpp"
#include "geovor/lonlat/geometry.hpp"

namespace geovor {

/// How features are framed in a GeoJSON file.
enum class GeoJsonFraming {
  FeatureCollection,  ///< one RFC 7946 FeatureCollection
  NewlineDelimited,   ///< one feature per line (GeoJSONSeq without RS; ".geojsonl")
  RecordSeparated,    ///< RFC 8142: RS + feature + LF (".geojsons")
};

/// Opens a native GeoJSON writer; open_feature_writer() calls it for "GeoJSON" / "GeoJSONSeq".
/// `path` "-" writes to stdout (no temporary file: a failure there cannot be undone). Otherwise
/// the features go to a temporary file in the same directory (geovor/core/output_target.hpp: a
/// short name, removed on signals once install_output_cleanup() was called), renamed to `path` by
/// finish() without replacing a file that appeared meanwhile unless options.overwrite; the
/// temporary file is removed on any failure and by the destructor when finish() was not called. The temporary file is written with direct I/O (O_DIRECT, whole 4 KiB
/// blocks from an aligned 4 MB buffer, the last partial block normally) where its file system
/// allows it, which spares the kernel's copy into the page cache; otherwise normally.
/// @exception Error(InvalidArgument) for a bad schema, id_field or precision (0..17);
///   Error(Io) if `path` exists and !options.overwrite, or cannot be created.
std::unique_ptr<FeatureWriter> open_geojson_writer(const std::string& path, GeoJsonFraming framing,
                                                   GeometryType geometry_type,
                                                   const std::vector<Field>& schema,
                                                   const WriterOptions& options);

/// As above, the text handed to `sink` as it is made (in order, on the writing thread) instead of
/// a file: a service's response. The same bytes as the file; finish() adds a collection's end.
std::unique_ptr<FeatureWriter> open_geojson_writer(std::function<void(std::string_view)> sink, GeoJsonFraming framing,
                                                   GeometryType geometry_type, const std::vector<Field>& schema,
                                                   const WriterOptions& options);

}  // namespace geovor
