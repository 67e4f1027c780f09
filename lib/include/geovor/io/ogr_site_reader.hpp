/// \file ogr_site_reader.hpp
/// \brief Sites from any OGR vector source (GeoPackage, Shapefile, GeoJSON, FlatGeobuf, ...) into
/// the same SiteTable as the CSV reader, and read_sites(), which picks the reader for a path.
///
/// A point layer gives one row per feature, in the layer's reading order:
/// - row: 1-based feature number; line: 0 (a feature has no line; the CSV reader's line numbers
///   do not apply);
/// - the position is the feature's Point geometry (a MultiPoint of exactly one point is taken
///   as that point; a Z value is ignored, height_m stays 0 as for latitude/longitude CSV input),
///   reprojected to EPSG:4326 (OAMS_TRADITIONAL_GIS_ORDER) when the layer has another SRS
///   (SiteReaderOptions::s_srs, when set, replaces the layer's own, as ogr2ogr -s_srs); a
///   layer without an SRS is taken as longitude/latitude degrees. Then normalize_lat_lon()
///   applies as for CSV;
/// - a point is checked before it reaches the transformation (source_domain below): a point
///   outside it is rejected ("point (1e+25, 1e+25) is outside the area of use of WGS 84 /
///   Pseudo-Mercator (EPSG:3857) ..."), never wrapped around the Earth nor left to stall PROJ;
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
#include <string_view>

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

/// As read_sites_ogr, from bytes in memory (a request's body: GeoJSON, GeoJSONSeq, ...) that GDAL
/// reads as a file named with `extension` (".geojson", ".geojsonl", ...); `name` replaces that
/// file's name in the table's source and in errors.
SiteTable read_sites_ogr_bytes(std::string_view bytes, const std::string& name, const std::string& extension,
                               const SiteReaderOptions& options = {});

/// Makes WGS84 sites of rows read with SiteReaderOptions::s_srs (x in lon_deg, y in lat_deg, in
/// the coordinates of `srs`): each point is checked against the domain of `srs` (below), then
/// transformed to EPSG:4326, normalised (normalize_lat_lon) and given its unit vector; a row that
/// fails is moved to the rejected rows with its reason (naming the columns), which stay in row
/// order.
///
/// The domain of a CRS: finite coordinates of magnitude at most 1e9 (PROJ spends time growing
/// with the magnitude: 1e18 m took 19 s in Web Mercator), and inside its area of use (PROJ's,
/// in degrees) widened by max(15 degrees, its width) in longitude and max(15 degrees, its height)
/// in latitude, cut at +-180 and +-90, then mapped into the CRS: so Norway in UTM zone 33 is
/// kept, while x beyond +-20037508.34 m in Web Mercator (another turn around the Earth) is
/// rejected. A CRS without an area of use is checked for finite magnitudes only.
/// 	hrow Error(ErrorCode::InvalidArgument) when GDAL does not know `srs`; Error(BadData) when it
///   cannot be transformed to EPSG:4326.
void reproject_sites(SiteTable& table, const std::string& srs);

/// Reads sites with the reader `path` calls for: is_csv_site_path() ones with
/// read_sites_csv_file() (then reproject_sites() with SiteReaderOptions::s_srs, when set), every
/// other path with read_sites_ogr() (GDAL recognises the format from the content and extension).
SiteTable read_sites(const std::string& path, const SiteReaderOptions& options = {});

/// True when read_sites() reads `path` as delimited text: "-" and every other stream
/// (is_stream_path()), whatever its name; the extensions .csv, .tsv, .txt, .dat and .psv (any
/// case); and a regular file with no or another extension than GDAL's formats (.gpkg, .geojson,
/// .json, .shp, .fgb, .gml, .kml, .tab, .xlsx, .zip, .gz, ... never) whose first 4 KiB, decoded
/// from `encoding` (SiteReaderOptions::encoding; UTF-8 when empty), hold no NUL byte, do not
/// start with '{', '[' or '<' (JSON, XML) and whose first line holds a delimiter (',', ';', TAB
/// or '|'). Every other path (GDAL's /vsi... files and
/// connection strings, directories, missing files) is OGR's.
bool is_csv_site_path(const std::string& path, const std::string& encoding = "");

/// True for "-" (stdin) and a path that is a pipe, FIFO, character device or socket (such as
/// `/dev/fd/63` from a shell's process substitution, or `/dev/stdin`): a source that can be read
/// only once, from its start. It is read as delimited text; one whose first bytes are not (a NUL
/// byte, or JSON or XML) is refused with ErrorCode::BadData (CsvSiteScan).
bool is_stream_path(const std::string& path);

}  // namespace geovor
