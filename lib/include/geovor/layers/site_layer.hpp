/// \file site_layer.hpp
/// \brief The site layer: every live site of a triangulation as a Point feature, with how far it
/// moved from a start position and the attributes of its input row (what `geovor relax
/// --sites-output` writes).
///
/// Fields (site_layer_schema()): site_index (Integer64), site_id (String: the id of the row the
/// site was built from; the GeoJSON feature id), lat_deg, lon_deg (Real: the site's geodetic
/// position now), moved_m (Real: great-circle distance from its start position on the sphere
/// of radius SiteEncoder::kEarthRadiusM), then the input columns but the positions (latitude
/// and longitude, or the ECEF X, Y, Z, which no longer hold), with their types, named as in the
/// input or renamed by input_columns.hpp's rule.
/// Features are written in site id order.
#pragma once

#include <cstddef>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "geovor/delaunay/site_rows.hpp"
#include "geovor/geo/site_reader.hpp"
#include "geovor/io/feature_writer.hpp"

namespace geovor {

/// The fields of the site layer of `table` (the file comment).
std::vector<Field> site_layer_schema(const SiteTable& table);

/// open_feature_writer(path, Point, site_layer_schema(table), options) with options.id_field set
/// to "site_id" unless the caller chose another field ("site_index" when ids repeat). @exception Error as open_feature_writer().
std::unique_ptr<FeatureWriter> open_site_layer_writer(const std::string& path, const SiteTable& table,
                                                      WriterOptions options);

/// Writes every live site of `dt` to `writer` (opened with site_layer_schema(table)), its
/// moved_m measured from start[s] (indexed by site id, size dt.site_capacity()); `rows` is
/// rows_of_sites() of its build. Does not finish the writer. Returns the sites written.
/// @exception Error as the writer.
std::size_t write_site_layer(FeatureWriter& writer, const SiteTable& table, const SiteRows& rows,
                             const SphericalDelaunay& dt, std::span<const Vec3> start);

}  // namespace geovor
