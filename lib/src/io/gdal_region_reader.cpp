#include <gdal_priv.h>
#include <ogr_feature.h>
#include <ogr_geometry.h>
#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>

#include <memory>

#include "geovor/core/error.hpp"
#include "geovor/io/ogr_region_reader.hpp"
#include "io/gdal_writer.hpp"

namespace geovor {
namespace {

FieldType field_type(OGRFieldType t) {
  switch (t) {
    case OFTInteger: return FieldType::Integer;
    case OFTInteger64: return FieldType::Integer64;
    case OFTReal: return FieldType::Real;
    case OFTDate: return FieldType::Date;
    case OFTDateTime: return FieldType::DateTime;
    default: return FieldType::String;
  }
}

FieldValue field_value(OGRFeature& f, int i, FieldType type) {
  if (!f.IsFieldSetAndNotNull(i)) return std::monostate{};
  switch (type) {
    case FieldType::Integer:
    case FieldType::Integer64: return static_cast<std::int64_t>(f.GetFieldAsInteger64(i));
    case FieldType::Real: return f.GetFieldAsDouble(i);
    default: return std::string(f.GetFieldAsString(i));
  }
}

Ring ring(const OGRLinearRing& r) {
  Ring out;
  out.reserve(static_cast<std::size_t>(r.getNumPoints()));
  for (int i = 0; i < r.getNumPoints(); ++i) out.push_back({r.getX(i), r.getY(i)});
  if (!out.empty() && (out.front().lon_deg != out.back().lon_deg || out.front().lat_deg != out.back().lat_deg))
    out.push_back(out.front());
  return out;
}

void add_polygon(const OGRPolygon& p, MultiPolygon& out) {
  if (p.IsEmpty()) return;
  Polygon polygon;
  polygon.exterior = ring(*p.getExteriorRing());
  for (int i = 0; i < p.getNumInteriorRings(); ++i) polygon.holes.push_back(ring(*p.getInteriorRing(i)));
  out.push_back(std::move(polygon));
}

}  // namespace

RegionTable read_regions_ogr(const std::string& path, const std::string& layer_name, const std::string& id_field) {
  gdal_detail::register_gdal();
  GDALDatasetUniquePtr dataset(GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY));
  if (!dataset) throw Error(ErrorCode::Io, path + ": cannot open as vector data: " + CPLGetLastErrorMsg());
  OGRLayer* layer = layer_name.empty() ? nullptr : dataset->GetLayerByName(layer_name.c_str());
  if (!layer_name.empty() && !layer) throw Error(ErrorCode::InvalidArgument, path + ": no layer '" + layer_name + "'");
  if (!layer) {
    if (dataset->GetLayerCount() != 1)
      throw Error(ErrorCode::InvalidArgument, path + ": " + std::to_string(dataset->GetLayerCount()) +
                                                  " layers; name the one of the regions");
    layer = dataset->GetLayer(0);
  }
  RegionTable table;
  table.source = path;
  OGRFeatureDefn* defn = layer->GetLayerDefn();
  int id_index = -1;
  for (int i = 0; i < defn->GetFieldCount(); ++i) {
    table.fields.push_back({defn->GetFieldDefn(i)->GetNameRef(), field_type(defn->GetFieldDefn(i)->GetType())});
    if (!id_field.empty() && EQUAL(defn->GetFieldDefn(i)->GetNameRef(), id_field.c_str())) id_index = i;
  }
  if (!id_field.empty() && id_index < 0)
    throw Error(ErrorCode::InvalidArgument, path + ": no field '" + id_field + "' for the regions' ids");
  std::unique_ptr<OGRCoordinateTransformation> to_wgs84;
  if (const OGRSpatialReference* srs = layer->GetSpatialRef()) {
    OGRSpatialReference wgs84;
    wgs84.SetWellKnownGeogCS("WGS84");
    wgs84.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    OGRSpatialReference source(*srs);
    source.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    if (!source.IsSame(&wgs84)) {
      to_wgs84.reset(OGRCreateCoordinateTransformation(&source, &wgs84));
      if (!to_wgs84) throw Error(ErrorCode::BadData, path + ": its CRS cannot be transformed to WGS84");
    }
  }
  layer->ResetReading();
  std::uint64_t row = 0;
  for (std::unique_ptr<OGRFeature> f(layer->GetNextFeature()); f; f.reset(layer->GetNextFeature())) {
    ++row;
    const std::string name = "feature " + std::to_string(row) + " (FID " + std::to_string(f->GetFID()) + ")";
    OGRGeometry* g = f->GetGeometryRef();
    auto reject = [&](const std::string& why) { table.rejected.push_back({row, 0, name + ": " + why}); };
    if (!g || g->IsEmpty()) {
      reject("no geometry");
      continue;
    }
    const OGRwkbGeometryType type = wkbFlatten(g->getGeometryType());
    if (type != wkbPolygon && type != wkbMultiPolygon) {
      reject(std::string("geometry is a ") + OGRGeometryTypeToName(type) + ", not a Polygon");
      continue;
    }
    if (to_wgs84 && g->transform(to_wgs84.get()) != OGRERR_NONE) {
      reject("cannot be transformed to WGS84");
      continue;
    }
    Region r;
    r.row = row;
    r.fid = f->GetFID();
    r.id = id_index >= 0 ? f->GetFieldAsString(id_index) : std::to_string(row);
    if (type == wkbPolygon) {
      add_polygon(*g->toPolygon(), r.geometry);
    } else {
      for (const OGRPolygon* p : *g->toMultiPolygon()) add_polygon(*p, r.geometry);
    }
    for (int i = 0; i < defn->GetFieldCount(); ++i) r.values.push_back(field_value(*f, i, table.fields[static_cast<std::size_t>(i)].type));
    table.regions.push_back(std::move(r));
  }
  return table;
}

}  // namespace geovor
