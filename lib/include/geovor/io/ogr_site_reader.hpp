/// \file ogr_site_reader.hpp
/// \brief Sites from any OGR vector source (GeoPackage, Shapefile, GeoJSON, FlatGeobuf, ...) into
/// the same SiteTable as the CSV reader, and read_sites(), which picks the reader for a path.
///
/// A point layer gives one row per feature, in the layer's reading order:
/// - row: 1-based feature number; line: 0 (a feature has no line; the CSV reader's line numbers
///   do not apply);
/// - the position is the feature's Point geometry (a MultiPoint of exactly one point is taken
///   as that point; a Z value is ignored, height_m stays 0 as for latitude/longitude CSV input),
///   reprojected to EPSG:4326 (OAMS_TRADITIONAL_GIS_ORDER) when the layer has another SRS; a
///   layer without an SRS is taken as longitude/latitude degrees. Then normalize_lat_lon()
///   applies as for CSV;
/// - rejected with a reason naming the feature: a null or empty geometry, a geometry that is not
///   a point ("feature 4 (FID 3): geometry is a LineString, not a Point"), a point that cannot
///   be transformed, a latitude beyond +-90;
/// - columns: the layer's attribute field names (not the FID, not the geometry); fields: every
///   attribute as text ("" for null or unset; Real fields in shortest round-trip form, so the
///   text reads back to the same double; others as GDAL formats them); lat_column, lon_column
///   and id_column are -1 and ecef_columns empty unless attribute columns are used (below);
/// - id: the SiteReaderOptions::id_field column, else a column named id, icao, code or name
///   (case-insensitive, as for CSV), else the row number.
///
/// Attribute positions: when SiteReaderOptions names latitude/longitude or ECEF columns, or the
/// layer has no geometry column (a GeoPackage attribute table, a spreadsheet), the positions come
/// from attribute columns with exactly the CSV reader's rules (detection, reasons), applied to
/// the attributes as text; reasons are then prefixed with "feature N (FID F): ".
#pragma once

#include <string>

#include "geovor/geo/site_reader.hpp"

namespace geovor {

/// Reads sites from `layer` of an OGR vector source (GDALDataset::Open with GDAL_OF_VECTOR; any
/// GDAL path works, including /vsizip/ and other virtual file systems).
/// \param[in] layer the layer name; "" for the only layer of the source.
/// \throw Error(Io) when `path` does not exist or reading fails midway; Error(BadData) when GDAL
///   cannot open it as vector data, it has no layer, or its SRS cannot be transformed to
///   EPSG:4326; Error(InvalidArgument) for an unknown layer, a source with several layers and
///   `layer` empty, or an option naming a column that does not exist.
SiteTable read_sites_ogr(const std::string& path, const SiteReaderOptions& options = {},
                         const std::string& layer = "");

/// Reads sites with the reader `path` calls for: "-" and the extensions .csv and .txt
/// (case-insensitive) go to read_sites_csv_file(); every other path to read_sites_ogr() (GDAL
/// recognises the format from the content and extension).
SiteTable read_sites(const std::string& path, const SiteReaderOptions& options = {});

/// True when read_sites() reads `path` with the CSV reader.
bool is_csv_site_path(const std::string& path);

}  // namespace geovor
