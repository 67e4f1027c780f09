#include <cpl_string.h>
#include <ogr_api.h>
#include <gdal_priv.h>
#include <ogr_feature.h>
#include <ogr_geometry.h>
#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>

#include <cstring>
#include <memory>

#include "geovor/core/error.hpp"
#include "geovor/io/json_text.hpp"
#include "geovor/io/number_format.hpp"
#include "geovor/io/ogr_feature_json.hpp"
#include "io/gdal_writer.hpp"

namespace geovor {
namespace {

// The feature's attributes as a JSON object.
std::string properties_json(OGRFeature& feature) {
  std::string out = "{";
  for (int i = 0; i < feature.GetFieldCount(); ++i) {
    const OGRFieldDefn* def = feature.GetFieldDefnRef(i);
    if (i > 0) out += ",";
    append_json_string(out, def->GetNameRef());
    out += ":";
    if (!feature.IsFieldSetAndNotNull(i)) {
      out += "null";
    } else if (def->GetType() == OFTInteger || def->GetType() == OFTInteger64) {
      out += std::to_string(feature.GetFieldAsInteger64(i));
    } else if (def->GetType() == OFTReal) {
      append_real(out, feature.GetFieldAsDouble(i));
    } else {
      append_json_string(out, feature.GetFieldAsString(i));
    }
  }
  return out + "}";
}

}  // namespace

JsonLayer read_json_features(const std::string& path, const std::string& layer_name) {
  gdal_detail::register_gdal();
  GDALDatasetUniquePtr dataset(GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY));
  if (!dataset) throw Error(ErrorCode::Io, path + ": cannot open as vector data: " + CPLGetLastErrorMsg());
  OGRLayer* layer = layer_name.empty() ? nullptr : dataset->GetLayerByName(layer_name.c_str());
  if (!layer_name.empty() && !layer) throw Error(ErrorCode::InvalidArgument, path + ": no layer '" + layer_name + "'");
  if (!layer) {
    if (dataset->GetLayerCount() != 1)
      throw Error(ErrorCode::InvalidArgument,
                  path + ": " + std::to_string(dataset->GetLayerCount()) + " layers; name the one to serve");
    layer = dataset->GetLayer(0);
  }
  std::unique_ptr<OGRCoordinateTransformation> to_wgs84;
  if (const OGRSpatialReference* srs = layer->GetSpatialRef()) {
    OGRSpatialReference wgs84;
    wgs84.SetWellKnownGeogCS("WGS84");
    wgs84.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    OGRSpatialReference source(*srs);
    source.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    if (!source.IsSame(&wgs84)) to_wgs84.reset(OGRCreateCoordinateTransformation(&source, &wgs84));
    if (!source.IsSame(&wgs84) && !to_wgs84)
      throw Error(ErrorCode::BadData, path + ": its CRS cannot be transformed to WGS84");
  }
  JsonLayer out;
  out.name = layer->GetName();
  char** options = CSLSetNameValue(nullptr, "SIGNIFICANT_FIGURES", "17");
  layer->ResetReading();
  for (std::unique_ptr<OGRFeature> f(layer->GetNextFeature()); f; f.reset(layer->GetNextFeature())) {
    JsonFeature j;
    j.fid = f->GetFID();
    j.properties = properties_json(*f);
    OGRGeometry* g = f->GetGeometryRef();
    if (g && to_wgs84 && g->transform(to_wgs84.get()) != OGRERR_NONE)
      throw Error(ErrorCode::BadData, path + ": feature " + std::to_string(j.fid) + ": cannot transform its geometry to WGS84");
    if (g && !g->IsEmpty()) {
      char* text = OGR_G_ExportToJsonEx(OGRGeometry::ToHandle(g), options);
      j.geometry = text ? text : "null";
      CPLFree(text);
      OGREnvelope e;
      g->getEnvelope(&e);
      j.bbox = {e.MinX, e.MinY, e.MaxX, e.MaxY};
    } else {
      j.geometry = "null";
    }
    out.features.push_back(std::move(j));
  }
  CSLDestroy(options);
  return out;
}

}  // namespace geovor
