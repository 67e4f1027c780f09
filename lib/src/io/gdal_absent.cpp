// The GDAL entry points of a library built without GDAL (geovor_without_gdal, linked by the
// geovor tool so that it starts without loading GDAL's 115 shared libraries). The tool hands
// every job that needs GDAL to geovor-gdal before it reaches these; reaching one is a bug.
#include <memory>
#include <string>

#include "geovor/core/error.hpp"
#include "geovor/io/ogr_feature_json.hpp"
#include "geovor/io/ogr_region_reader.hpp"
#include "geovor/io/ogr_site_reader.hpp"
#include "io/gdal_writer.hpp"

namespace geovor {
namespace {

[[noreturn]] void absent(const std::string& path, const char* what) {
  throw Error(ErrorCode::Internal, path + ": " + what + " needs GDAL, which this build of the library does not link (use geovor-gdal or the geovor library)");
}

}  // namespace

SiteTable read_sites_ogr(const std::string& path, const SiteReaderOptions&, const std::string&) {
  absent(path, "reading an OGR source");
}

SiteTable read_sites_ogr_bytes(std::string_view, const std::string& name, const std::string&, const SiteReaderOptions&) {
  absent(name, "reading GeoJSON from memory");
}

void reproject_sites(SiteTable& table, const std::string&) { absent(table.source, "--s-srs (reprojecting sites)"); }

RegionTable read_regions_ogr(const std::string& path, const std::string&, const std::string&) {
  absent(path, "reading regions");
}

JsonLayer read_json_features(const std::string& path, const std::string&) { absent(path, "reading an OGR layer"); }

namespace gdal_detail {

std::string driver_for_extension(const std::string& path) { absent(path, "choosing a GDAL driver"); }

bool driver_holds_layers(const std::string& driver) { absent(driver, "asking a GDAL driver"); }

// No refusal known here: open_gdal_writer, called next, throws naming the path.
std::string format_refusal(const std::string&, GeometryType, const WriterOptions&) { return {}; }

std::unique_ptr<FeatureWriter> open_gdal_writer(const std::string& path, const std::string& driver,
                                                GeometryType, const std::vector<Field>&, const WriterOptions&) {
  absent(path, ("writing " + driver).c_str());
}

}  // namespace gdal_detail
}  // namespace geovor
