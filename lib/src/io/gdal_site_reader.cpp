#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_vsi.h>
#include <gdal_priv.h>
#include <ogr_feature.h>
#include <ogr_geometry.h>
#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <optional>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <string_view>
#include <system_error>

#include "geovor/core/error.hpp"
#include "geovor/geo/column_types.hpp"
#include "geovor/geo/lat_lon.hpp"
#include "geovor/geo/site_encoder.hpp"
#include "geovor/io/ogr_site_reader.hpp"
#include "geo/trim.hpp"
#include "io/gdal_writer.hpp"

namespace geovor {
namespace {

namespace fs = std::filesystem;
using gdal_detail::ErrorCapture;

constexpr std::array<std::string_view, 4> kIdNames = {"id", "icao", "code", "name"};

// As the CSV reader: names compared trimmed and case-insensitively.
std::string list_names(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

// A field's value as text; "" when null or unset.
std::string field_text(const OGRFeature& f, int i) {
  if (!f.IsFieldSetAndNotNull(i)) return "";
  const OGRFieldDefn* defn = f.GetFieldDefnRef(i);
  switch (defn->GetType()) {
    case OFTInteger:
    case OFTInteger64:
      return std::to_string(f.GetFieldAsInteger64(i));
    case OFTReal: {
      char buf[32];
      const double v = f.GetFieldAsDouble(i);
      if (!std::isfinite(v)) return "";  // no JSON number: null (column_types.hpp's invariant)
      return std::string(buf, std::to_chars(buf, buf + sizeof buf, v).ptr);
    }
    case OFTDate:
    case OFTDateTime: {
      // ISO 8601, as column_types.hpp reads dates (GDAL's own text has slashes).
      int y = 0, mo = 0, d = 0, h = 0, mi = 0, tz = 0;
      float sec = 0;
      f.GetFieldAsDateTime(i, &y, &mo, &d, &h, &mi, &sec, &tz);
      char buf[64];
      int n = std::snprintf(buf, sizeof buf, "%04d-%02d-%02d", y, mo, d);
      if (defn->GetType() == OFTDateTime) {
        const int ms = static_cast<int>(std::lround(sec * 1000));
        n += std::snprintf(buf + n, sizeof buf - n, "T%02d:%02d:%02d", h, mi, ms / 1000);
        if (ms % 1000 != 0) n += std::snprintf(buf + n, sizeof buf - n, ".%03d", ms % 1000);
        if (tz == 100) {
          n += std::snprintf(buf + n, sizeof buf - n, "Z");
        } else if (tz > 1) {  // 1: local time, 0: unknown; else 100 + quarters of an hour
          const int q = std::abs(tz - 100);
          n += std::snprintf(buf + n, sizeof buf - n, "%c%02d:%02d", tz > 100 ? '+' : '-', q / 4, q % 4 * 15);
        }
      }
      return std::string(buf, static_cast<std::size_t>(n));
    }
    default:
      return f.GetFieldAsString(i);
  }
}

// The type a column of this OGR type keeps; lists, times and binaries are text.
FieldType field_type(OGRFieldType type) {
  switch (type) {
    case OFTInteger:
      return FieldType::Integer;
    case OFTInteger64:
      return FieldType::Integer64;
    case OFTReal:
      return FieldType::Real;
    case OFTDate:
      return FieldType::Date;
    case OFTDateTime:
      return FieldType::DateTime;
    default:
      return FieldType::String;
  }
}

// RFC 4180 field for the CSV reader.
void append_csv(std::string& out, const std::string& value) {
  if (value.find_first_of(",\"\r\n") == std::string::npos && trim(value) == value) {
    out += value;
    return;
  }
  out += '"';
  for (char c : value) {
    if (c == '"') out += '"';
    out += c;
  }
  out += '"';
}

std::string feature_name(std::uint64_t row, GIntBig fid) {
  std::string s = "feature " + std::to_string(row);
  if (fid != OGRNullFID) s += " (FID " + std::to_string(fid) + ")";
  return s;
}

// Positions from attribute columns: the attributes become CSV text for read_sites_csv, so that
// detection and reasons are exactly the CSV reader's.
SiteTable read_attribute_positions(OGRLayer& layer, const std::string& source,
                                   const std::vector<std::string>& columns,
                                   const SiteReaderOptions& options, ErrorCapture& capture) {
  std::string csv;
  for (std::size_t i = 0; i < columns.size(); ++i) {
    if (i > 0) csv += ',';
    append_csv(csv, columns[i]);
  }
  csv += '\n';
  std::vector<GIntBig> fids;
  layer.ResetReading();
  for (const auto& feature : layer) {
    fids.push_back(feature->GetFID());
    for (int i = 0; i < static_cast<int>(columns.size()); ++i) {
      if (i > 0) csv += ',';
      append_csv(csv, field_text(*feature, i));
    }
    csv += '\n';
  }
  if (capture.failed()) {
    throw Error(ErrorCode::Io, source + ": cannot read feature " +
                                   std::to_string(fids.size() + 1) + capture.detail());
  }
  std::istringstream in(csv);
  SiteReaderOptions csv_options = options;
  csv_options.delimiter = ',';  // as written above, whatever the names hold
  csv_options.encoding.clear();  // GDAL gives UTF-8
  SiteTable table = read_sites_csv(in, source, csv_options);
  for (InputSite& s : table.sites) s.line = 0;
  for (RejectedRow& r : table.rejected) {
    r.reason = feature_name(r.row, r.row - 1 < fids.size() ? fids[r.row - 1] : OGRNullFID) +
               ": " + r.reason;
    r.line = 0;
  }
  return table;
}

// The transformation of a source CRS to EPSG:4326 (longitude first) and the source coordinates
// it accepts (reproject_sites() in ogr_site_reader.hpp documents the domain).
class SourceTransform {
 public:
  // `srs` with any axis mapping; throws when it cannot be transformed.
  SourceTransform(const OGRSpatialReference& srs, const std::string& source, ErrorCapture& capture) {
    OGRSpatialReference source_srs(srs);
    source_srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    OGRSpatialReference wgs84;
    wgs84.importFromEPSG(4326);
    wgs84.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    const char* same_options[] = {"IGNORE_DATA_AXIS_TO_SRS_AXIS_MAPPING=YES",
                                  "CRITERION=EQUIVALENT_EXCEPT_AXIS_ORDER_GEOGCRS", nullptr};
    if (source_srs.IsSame(&wgs84, same_options)) return;
    name_ = source_srs.GetName() != nullptr ? source_srs.GetName() : "the source SRS";
    if (const char* code = source_srs.GetAuthorityCode(nullptr)) {
      const char* auth = source_srs.GetAuthorityName(nullptr);
      name_ += std::string(" (") + (auth != nullptr ? auth : "") + ":" + code + ")";
    }
    transform_.reset(OGRCreateCoordinateTransformation(&source_srs, &wgs84));
    if (!transform_)
      throw Error(ErrorCode::BadData, source + ": cannot transform " + name_ + " to EPSG:4326" + capture.detail());
    double west = 0, south = 0, east = 0, north = 0;
    const char* area = nullptr;
    if (!source_srs.GetAreaOfUse(&west, &south, &east, &north, &area) || west < -1000) return;
    if (east < west) east += 360;  // an area across the antimeridian
    const double lon_margin = std::max(15.0, east - west), lat_margin = std::max(15.0, north - south);
    west = std::max(-180.0, west - lon_margin);
    east = std::min(180.0, east + lon_margin);
    south = std::max(-90.0, south - lat_margin);
    north = std::min(90.0, north + lat_margin);
    std::unique_ptr<OGRCoordinateTransformation> inverse(OGRCreateCoordinateTransformation(&wgs84, &source_srs));
    double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    if (inverse && inverse->TransformBounds(west, south, east, north, &x0, &y0, &x1, &y1, 21)) {
      // A hair wider, so that a point on the edge (x = 20037508.342789244 in Web Mercator) stays in.
      const double tx = 1e-9 * (std::abs(x0) + std::abs(x1)), ty = 1e-9 * (std::abs(y0) + std::abs(y1));
      bounds_ = {x0 - tx, y0 - ty, x1 + tx, y1 + ty};
      has_bounds_ = std::isfinite(x0) || std::isfinite(x1) || std::isfinite(y0) || std::isfinite(y1);
      bounds_text_ = "x from " + number(x0) + " to " + number(x1) + ", y from " + number(y0) + " to " + number(y1);
    }
    capture.clear();
  }

  bool identity() const { return !transform_; }
  const std::string& name() const { return name_; }

  // (x, y) to longitude/latitude; "" on success, else the reason.
  std::string to_lon_lat(double& x, double& y) {
    if (!transform_) return "";
    const std::string point = "point (" + number(x) + ", " + number(y) + ")";
    if (!std::isfinite(x) || !std::isfinite(y)) return point + " is not finite";
    if (std::abs(x) > kMaxMagnitude || std::abs(y) > kMaxMagnitude)
      return point + " is far outside " + name_ + " (a coordinate beyond 1e9)";
    // NaN-free comparisons: an infinite bound (a pole in Mercator) bounds nothing.
    if (has_bounds_ && (x < bounds_[0] || x > bounds_[2] || y < bounds_[1] || y > bounds_[3]))
      return point + " is outside the area of use of " + name_ + " (" + bounds_text_ + ", with a margin)";
    int ok = 0;
    const double x_in = x, y_in = y;
    if (!transform_->Transform(1, &x, &y, nullptr, &ok) || !ok) {
      x = x_in;
      y = y_in;
      return point + " cannot be transformed from " + name_ + " to EPSG:4326";
    }
    return "";
  }

 private:
  static constexpr double kMaxMagnitude = 1e9;
  static std::string number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.10g", v);
    return buf;
  }
  std::unique_ptr<OGRCoordinateTransformation> transform_;
  std::string name_;
  std::array<double, 4> bounds_{};
  bool has_bounds_ = false;
  std::string bounds_text_;
};

// The SRS a user named (--s-srs): anything SetFromUserInput takes.
OGRSpatialReference user_srs(const std::string& text) {
  OGRSpatialReference srs;
  if (srs.SetFromUserInput(text.c_str()) != OGRERR_NONE)
    throw Error(ErrorCode::InvalidArgument, "--s-srs " + text + ": not a coordinate system GDAL knows (EPSG:2154, a WKT or a PROJ string)");
  return srs;
}

}  // namespace

void reproject_sites(SiteTable& table, const std::string& srs_text) {
  gdal_detail::register_gdal();
  ErrorCapture capture;
  const OGRSpatialReference srs = user_srs(srs_text);
  SourceTransform transform(srs, table.source, capture);
  std::string columns;
  if (table.lon_column >= 0 && table.lat_column >= 0)
    columns = table.columns[static_cast<std::size_t>(table.lon_column)] + ", " +
              table.columns[static_cast<std::size_t>(table.lat_column)] + ": ";
  std::vector<InputSite> kept;
  kept.reserve(table.sites.size());
  const std::size_t rejected_before = table.rejected.size();
  for (InputSite& site : table.sites) {
    double x = site.lon_deg, y = site.lat_deg;
    std::string reason = transform.to_lon_lat(x, y);
    if (reason.empty()) {
      site.lon_deg = x;
      site.lat_deg = y;
      reason = normalize_lat_lon(site.lat_deg, site.lon_deg);
    }
    if (!reason.empty()) {
      table.rejected.push_back(RejectedRow{site.row, site.line, columns + reason});
      continue;
    }
    site.unit = SiteEncoder::from_lat_lon(site.lat_deg, site.lon_deg);
    kept.push_back(std::move(site));
  }
  capture.clear();
  table.sites = std::move(kept);
  if (table.rejected.size() > rejected_before)
    std::sort(table.rejected.begin(), table.rejected.end(),
              [](const RejectedRow& a, const RejectedRow& b) { return a.row < b.row; });
}

SiteTable read_sites_ogr(const std::string& path, const SiteReaderOptions& options,
                         const std::string& layer_name) {
  if (!options.ecef_fields.empty() && options.ecef_fields.size() != 3) {
    throw Error(ErrorCode::InvalidArgument, "ECEF input needs exactly 3 columns (X, Y, Z), got " +
                                                std::to_string(options.ecef_fields.size()));
  }
  gdal_detail::register_gdal();
  // A plain file name that does not exist: say so as the CSV reader does. GDAL's virtual file
  // systems (/vsizip/...) and connection strings ("PG:...") are left to GDAL.
  std::error_code ec;
  const bool special = path.rfind("/vsi", 0) == 0 || path.find(':') != std::string::npos;
  if (!special && !fs::exists(path, ec)) {
    throw Error(ErrorCode::Io, path + ": cannot open: " + std::strerror(ENOENT));
  }
  ErrorCapture capture;
  GDALDatasetUniquePtr dataset(
      GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY | GDAL_OF_VERBOSE_ERROR));
  if (!dataset) {
    // GDAL does not look inside a plain .gz on its own; say how to make it.
    char magic[2] = {};
    if (std::FILE* f = special ? nullptr : std::fopen(path.c_str(), "rb")) {
      const bool gzip = std::fread(magic, 1, 2, f) == 2 && magic[0] == '\x1f' && magic[1] == '\x8b';
      std::fclose(f);
      if (gzip)
        throw Error(ErrorCode::BadData, path + ": gzip-compressed; decompress it (gzip -dk " + path +
                                            ") or give it to GDAL as /vsigzip/" + path);
    }
    throw Error(special ? ErrorCode::Io : ErrorCode::BadData,
                path + ": not a vector data source GDAL can read" + capture.detail());
  }
  OGRLayer* layer = nullptr;
  std::vector<std::string> layer_names;
  for (int i = 0; i < dataset->GetLayerCount(); ++i) {
    layer_names.emplace_back(dataset->GetLayer(i)->GetName());
  }
  if (!layer_name.empty()) {
    layer = dataset->GetLayerByName(layer_name.c_str());
    if (layer == nullptr) {
      throw Error(ErrorCode::InvalidArgument, path + ": no layer '" + layer_name +
                                                  "'; layers: " + list_names(layer_names));
    }
  } else if (layer_names.empty()) {
    throw Error(ErrorCode::BadData, path + ": no layer");
  } else if (layer_names.size() > 1) {
    throw Error(ErrorCode::InvalidArgument,
                path + ": " + std::to_string(layer_names.size()) +
                    " layers; choose one of them (--layer NAME): " + list_names(layer_names));
  } else {
    layer = dataset->GetLayer(0);
  }

  SiteTable table;
  table.source = path;
  OGRFeatureDefn* defn = layer->GetLayerDefn();
  for (int i = 0; i < defn->GetFieldCount(); ++i) {
    table.columns.emplace_back(defn->GetFieldDefn(i)->GetNameRef());
    table.column_types.push_back(options.detect_types ? field_type(defn->GetFieldDefn(i)->GetType())
                                                      : FieldType::String);
  }
  const bool attribute_positions = !options.lat_field.empty() || !options.lon_field.empty() ||
                                   !options.ecef_fields.empty() || defn->GetGeomFieldCount() == 0;
  if (attribute_positions) {
    SiteTable from_attributes = read_attribute_positions(*layer, path, table.columns, options, capture);
    from_attributes.column_types = table.column_types;  // the layer's own types, not guessed ones
    apply_field_types(from_attributes, options.field_types);
    if (!options.s_srs.empty()) reproject_sites(from_attributes, options.s_srs);
    return from_attributes;
  }

  if (options.id_field == kRowNumberId) {
    table.id_column = -1;
  } else if (!options.id_field.empty()) {
    table.id_column = find_column(table.columns, options.id_field);
    if (table.id_column < 0) {
      throw Error(ErrorCode::InvalidArgument, path + ": id field '" + options.id_field +
                                                  "' is not a column; found columns: " +
                                                  list_names(table.columns));
    }
  } else {
    for (const auto name : kIdNames) {
      if ((table.id_column = find_column(table.columns, name)) >= 0) break;
    }
  }

  // The transformation to EPSG:4326, longitude first; none when the layer is already in it.
  std::optional<SourceTransform> transform;
  if (!options.s_srs.empty())
    transform.emplace(user_srs(options.s_srs), path, capture);
  else if (const OGRSpatialReference* layer_srs = layer->GetSpatialRef())
    transform.emplace(*layer_srs, path, capture);

  const int field_count = defn->GetFieldCount();
  layer->ResetReading();
  for (const auto& feature : *layer) {
    ++table.rows_read;
    const std::uint64_t row = table.rows_read;
    auto reject = [&](const std::string& reason) {
      table.rejected.push_back(
          RejectedRow{row, 0, feature_name(row, feature->GetFID()) + ": " + reason});
    };
    const OGRGeometry* g = feature->GetGeometryRef();
    if (g == nullptr) {
      reject("geometry is null");
      continue;
    }
    if (g->IsEmpty()) {
      reject("geometry is empty (" + std::string(OGRGeometryTypeToName(g->getGeometryType())) +
             ")");
      continue;
    }
    const OGRPoint* point = nullptr;
    const OGRwkbGeometryType type = wkbFlatten(g->getGeometryType());
    if (type == wkbPoint) {
      point = g->toPoint();
    } else if (type == wkbMultiPoint && g->toMultiPoint()->getNumGeometries() == 1) {
      point = g->toMultiPoint()->getGeometryRef(0);
    } else if (type == wkbMultiPoint) {
      reject("geometry is a MultiPoint of " +
             std::to_string(g->toMultiPoint()->getNumGeometries()) + " points, not a Point");
      continue;
    } else {
      reject("geometry is a " + std::string(OGRGeometryTypeToName(type)) + ", not a Point");
      continue;
    }
    double x = point->getX();
    double y = point->getY();
    if (transform) {
      if (std::string reason = transform->to_lon_lat(x, y); !reason.empty()) {
        capture.clear();  // PROJ's message for this point is handled by the rejection
        reject(reason);
        continue;
      }
    }
    InputSite site;
    site.row = row;
    site.line = 0;
    site.lat_deg = y;
    site.lon_deg = x;
    if (auto reason = normalize_lat_lon(site.lat_deg, site.lon_deg); !reason.empty()) {
      reject(reason);
      continue;
    }
    site.unit = SiteEncoder::from_lat_lon(site.lat_deg, site.lon_deg);
    site.fields.reserve(static_cast<std::size_t>(field_count));
    for (int i = 0; i < field_count; ++i) site.fields.push_back(field_text(*feature, i));
    site.id = table.id_column >= 0 ? site.fields[static_cast<std::size_t>(table.id_column)]
                                   : std::to_string(row);
    table.sites.push_back(std::move(site));
  }
  // A read error ends GDAL's iteration early; it must not pass for the end of the layer.
  if (capture.failed()) {
    throw Error(ErrorCode::Io, path + ": cannot read feature " +
                                   std::to_string(table.rows_read + 1) + capture.detail());
  }
  apply_field_types(table, options.field_types);
  return table;
}

SiteTable read_sites_ogr_bytes(std::string_view bytes, const std::string& name, const std::string& extension,
                               const SiteReaderOptions& options) {
  gdal_detail::register_gdal();
  static std::atomic<std::uint64_t> serial{0};
  const std::string path = "/vsimem/geovor_bytes_" + std::to_string(serial++) + extension;
  VSIFCloseL(VSIFileFromMemBuffer(path.c_str(), reinterpret_cast<GByte*>(const_cast<char*>(bytes.data())),
                                  static_cast<vsi_l_offset>(bytes.size()), FALSE));
  auto renamed = [&](std::string text) {
    for (std::size_t at = text.find(path); at != std::string::npos; at = text.find(path, at + name.size()))
      text.replace(at, path.size(), name);
    return text;
  };
  try {
    SiteTable table = read_sites_ogr(path, options);
    VSIUnlink(path.c_str());
    table.source = name;
    return table;
  } catch (const Error& e) {
    VSIUnlink(path.c_str());
    throw Error(e.code(), renamed(e.what()));
  }
}

}  // namespace geovor
