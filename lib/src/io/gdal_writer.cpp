#include "io/gdal_writer.hpp"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_string.h>
#include <gdal.h>
#include <gdal_priv.h>
#include <ogr_core.h>
#include <ogr_feature.h>
#include <ogr_geometry.h>
#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <set>
#include <span>
#include <string_view>
#include <system_error>
#include <utility>

#include "geovor/core/ascii.hpp"
#include "geovor/core/error.hpp"
#include "geovor/io/geojson_writer.hpp"
#include "geovor/core/output_target.hpp"

namespace geovor::gdal_detail {
namespace {

namespace fs = std::filesystem;

// A DBF or MapInfo field holds at most 254 bytes.
constexpr std::size_t kShapefileMaxBytes = 254;

void CPL_STDCALL capture_handler(CPLErr error_class, CPLErrorNum number, const char* message) {
  auto* capture = static_cast<ErrorCapture*>(CPLGetErrorHandlerUserData());
  // A driver that cuts a value only warns: a failure here, since nothing may be cut silently.
  if (error_class == CE_Warning && capture != nullptr && message != nullptr && std::strstr(message, "truncat")) {
    capture->record(static_cast<int>(CE_Failure), message);
    return;
  }
  if (error_class == CE_Warning) {
    CPLDefaultErrorHandler(error_class, number, message);
    return;
  }
  if (capture != nullptr) capture->record(static_cast<int>(error_class), message);
}


// Sidecar extensions that a previous output of the same name may have left and that would be
// read together with the new one; removed when it is replaced (--overwrite).
std::vector<std::string> stale_sidecars(const std::string& driver) {
  if (ascii_iequals(driver, "ESRI Shapefile")) {
    return {"shp", "shx", "dbf", "prj", "cpg", "qix", "sbn", "sbx", "qpj"};
  }
  if (ascii_iequals(driver, "CSV")) return {"csvt"};  // types GDAL would apply on reading
  if (ascii_iequals(driver, "MapInfo File")) return {"tab", "dat", "map", "id", "ind", "mif", "mid"};
  return {};
}

// The formats that hold every layer geovor writes, less `driver`: "GeoPackage, FlatGeobuf or GeoJSON".
std::string other_formats(const std::string& driver) {
  std::vector<std::string> names;
  for (const auto& [name, description] : {std::pair{"GPKG", "GeoPackage"}, {"FlatGeobuf", "FlatGeobuf"}, {"GeoJSON", "GeoJSON"}})
    if (!ascii_iequals(driver, name)) names.emplace_back(description);
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i) out += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
  return out;
}

class GdalWriter final : public FeatureWriter {
 public:
  GdalWriter(const std::string& path, const std::string& driver_name, GeometryType geometry_type,
             const std::vector<Field>& schema, const WriterOptions& options)
      : path_(path),
        geometry_type_(geometry_type),
        field_count_(schema.size()),
        overwrite_(options.overwrite),
        options_(options) {
    register_gdal();
    ErrorCapture capture;
    GDALDriver* driver = GetGDALDriverManager()->GetDriverByName(driver_name.c_str());
    if (driver == nullptr || driver->GetMetadataItem(GDAL_DCAP_VECTOR) == nullptr ||
        driver->GetMetadataItem(GDAL_DCAP_CREATE) == nullptr) {
      throw Error(ErrorCode::InvalidArgument,
                  "unknown output format '" + driver_name +
                      "': not a GDAL vector driver that can create files (see ogrinfo --formats)");
    }
    driver_ = driver->GetDescription();
    if (const std::string why = format_refusal(driver_, geometry_type, options); !why.empty())
      throw Error(ErrorCode::InvalidArgument, path_ + ": " + why);
    // GDAL's GPX writer mixes a field named as one of GPX's own elements up with it (a `name`
    // column's value landed in another field): refused, naming it.
    if (ascii_iequals(driver_, "GPX"))
      for (const Field& f : schema)
        for (const char* own : {"ele", "time", "magvar", "geoidheight", "name", "cmt", "desc", "src", "sym", "type",
                                "fix", "sat", "hdop", "vdop", "pdop", "ageofdgpsdata", "dgpsid", "number"})
          if (ascii_iequals(f.name, own) || ascii_lower(f.name).starts_with("link"))
            throw Error(ErrorCode::InvalidArgument,
                        path_ + ": field '" + f.name + "' has the name of one of GPX's own elements, which GDAL's GPX "
                                "writer would mix it up with; write " + other_formats(driver_));
    if (path_ == "-") {
      throw Error(ErrorCode::InvalidArgument,
                  "format " + driver_ + " cannot be written to stdout; only GeoJSON and GeoJSONSeq can");
    }
    const fs::path target(path_);
    if (!target.has_filename()) throw Error(ErrorCode::InvalidArgument, path_ + ": not a file name");
    layered_ = driver->GetMetadataItem(GDAL_DCAP_MULTIPLE_VECTOR_LAYERS) != nullptr;
    if (options.update && !layered_)
      throw Error(ErrorCode::InvalidArgument, path_ + ": --update adds a layer to a data source that holds several (GPKG, SQLite, ...); " +
                                                  driver_ + " holds one: use --overwrite to replace the file");
    // ogr2ogr's model: an existing data source of a multi-layer format keeps its other layers.
    std::error_code ec;
    updating_ = layered_ && (options.update || options.overwrite) && fs::exists(fs::symlink_status(target, ec));
    if (updating_)
      check_updatable(target);
    else
      check_targets(target, options.overwrite);

    // The private temporary directory, next to the target (same file system: rename works), with
    // a short name (output_target.hpp), removed on errors and signals.
    temp_ = TemporaryOutput(path_, TemporaryOutput::Kind::Directory);
    temp_dir_ = temp_.path();
    try {
      // --overwrite of a file that is no data source of the format replaces the file.
      if (updating_ && !open_copy(target, options.update)) updating_ = false;
      create(driver, target.filename().string(), schema, options);
    } catch (...) {
      discard();
      throw;
    }
  }

  ~GdalWriter() override {
    if (!finished_) {
      ErrorCapture capture;  // errors while abandoning the output are of no interest
      discard();
    }
  }

  void write(const Geometry& geometry, std::span<const FieldValue> values) override {
    if (failed_) throw Error(ErrorCode::Io, path_ + ": the writer failed earlier");
    if (finished_) throw Error(ErrorCode::InvalidArgument, path_ + ": write() after finish()");
    auto feature = [&] { return "feature " + std::to_string(count_ + 1); };
    if (values.size() != field_count_) {
      throw Error(ErrorCode::InvalidArgument,
                  path_ + ": " + feature() + " has " + std::to_string(values.size()) +
                      " values for " + std::to_string(field_count_) + " fields");
    }
    if (static_cast<GeometryType>(geometry.index()) != geometry_type_) {
      throw Error(ErrorCode::InvalidArgument,
                  path_ + ": " + feature() + " is a " +
                      to_string(static_cast<GeometryType>(geometry.index())) + " in a " +
                      to_string(geometry_type_) + " layer");
    }
    if (auto why = geometry_problem(geometry); !why.empty()) {
      throw Error(ErrorCode::InvalidArgument, path_ + ": " + feature() + ": " + why);
    }
    if (ascii_iequals(driver_, "FlatGeobuf")) {
      // GDAL's FlatGeobuf writer leaves out a feature with an empty geometry (its spatial index
      // has no box for it): refused, never dropped.
      const auto* polygons = std::get_if<MultiPolygon>(&geometry);
      const auto* lines = std::get_if<MultiLineString>(&geometry);
      const auto* point = std::get_if<LonLat>(&geometry);
      if (point && is_null_point(*point))
        throw Error(ErrorCode::BadData,
                    path_ + ": " + feature() + " has a null point (a row without a position), which FlatGeobuf cannot "
                    "hold (GDAL would leave the feature out); write GeoPackage or GeoJSON");
      if ((polygons && polygons->empty()) || (lines && lines->empty()))
        throw Error(ErrorCode::BadData,
                    path_ + ": " + feature() + " has an empty geometry, which FlatGeobuf cannot hold (GDAL "
                    "would leave the feature out); write GeoPackage or GeoJSON, or raise --precision");
    }
    set_values(values, feature());
    ErrorCapture capture;
    OGRFeature& f = *feature_;
    f.SetGeometryDirectly(to_ogr(geometry));
    f.SetFID(OGRNullFID);
    errno = 0;
    if (layer_->CreateFeature(&f) != OGRERR_NONE || capture.failed()) {
      fail("cannot write " + feature() + detail(capture));
    }
    ++count_;
  }

  void start_layer(const std::string& layer, GeometryType geometry_type, const std::vector<Field>& schema) override {
    if (failed_) throw Error(ErrorCode::Io, path_ + ": the writer failed earlier");
    if (finished_) throw Error(ErrorCode::InvalidArgument, path_ + ": next_layer() after finish()");
    if (!layered_)
      throw Error(ErrorCode::InvalidArgument, path_ + ": " + driver_ + " holds one layer; layer '" + layer +
                                                  "' needs another file, or a format that holds several (GPKG, SQLite, ...)");
    if (std::find_if(written_layers_.begin(), written_layers_.end(),
                     [&](const std::string& n) { return ascii_iequals(n, layer); }) != written_layers_.end())
      throw Error(ErrorCode::InvalidArgument, path_ + ": two layers named '" + layer + "'; name them apart");
    ErrorCapture capture;
    // The layer written so far is complete; each layer is one transaction.
    if (transaction_ && dataset_->CommitTransaction() != OGRERR_NONE) fail("cannot commit" + capture.detail());
    transaction_ = false;
    feature_.reset();
    field_index_.clear();
    geometry_type_ = geometry_type;
    field_count_ = schema.size();
    count_ = 0;
    WriterOptions options = options_;
    options.layer = layer;
    create(nullptr, "", schema, options);
  }

  void finish() override {
    if (failed_) throw Error(ErrorCode::Io, path_ + ": the writer failed earlier");
    if (finished_) return;
    ErrorCapture capture;
    if (transaction_ && dataset_->CommitTransaction() != OGRERR_NONE) {
      fail("cannot commit" + capture.detail());
    }
    transaction_ = false;
    feature_.reset();
    // Closing writes what the driver buffered (FlatGeobuf writes its whole file here).
    errno = 0;
    GDALClose(GDALDataset::ToHandle(std::exchange(dataset_, nullptr)));
    layer_ = nullptr;
    if (capture.failed()) fail("cannot write" + detail(capture));
    move_into_place();
    finished_ = true;
  }

 private:
  // Error(Io) when the output or, for multi-file formats, one of its sidecars exists and may
  // not be replaced.
  void check_targets(const fs::path& target, bool overwrite) const {
    std::vector<fs::path> paths{target};
    for (const std::string& ext : stale_sidecars(driver_)) {
      fs::path p = target;
      paths.push_back(p.replace_extension(ext));
    }
    for (const fs::path& p : paths) {
      std::error_code ec;
      if (!fs::exists(fs::symlink_status(p, ec))) continue;
      if (fs::is_directory(fs::status(p, ec))) {
        throw Error(ErrorCode::Io, p.string() + ": is a directory");
      }
      // Renaming over a device or a FIFO (/dev/null as root) would replace it.
      if (fs::exists(fs::status(p, ec)) && !fs::is_regular_file(fs::status(p, ec))) {
        throw Error(ErrorCode::Io, p.string() + ": not a regular file; " + driver_ + " output must be one");
      }
      if (!overwrite) {
        throw Error(ErrorCode::Io, output_exists(p.string(), layered_ ? " (its layer of that name only), or --update to add a layer to it" : ""));
      }
    }
  }

  // An existing data source to update: a regular file, not open in another program (an SQLite
  // journal beside it would hold changes that a copy of the file alone lacks).
  void check_updatable(const fs::path& target) const {
    std::error_code ec;
    if (fs::is_directory(fs::status(target, ec))) throw Error(ErrorCode::Io, path_ + ": is a directory");
    if (!fs::is_regular_file(fs::status(target, ec)))
      throw Error(ErrorCode::Io, path_ + ": not a regular file; " + driver_ + " output must be one");
    for (const char* suffix : {"-wal", "-journal"})
      if (fs::exists(fs::symlink_status(path_ + suffix, ec)))
        throw Error(ErrorCode::Io, path_ + suffix + " exists: " + path_ +
                                       " is open in another program, or was not closed; close it before updating it");
  }

  // The existing data source, copied into the temporary directory and opened there for update:
  // the original is only replaced, whole, by move_into_place(). False, the copy removed, when
  // GDAL cannot open it as a data source of the format and `required` is false.
  bool open_copy(const fs::path& target, bool required) {
    ErrorCapture capture;
    const fs::path copy = temp_dir_ / target.filename();
    std::error_code ec;
    original_ = file_state(target);
    if (!fs::copy_file(target, copy, ec) || ec) fail("cannot copy it to " + copy.string() + " to update it: " + ec.message());
    if (file_state(target) != original_) fail("changed while it was being copied; not updated");
    const char* const drivers[] = {driver_.c_str(), nullptr};
    dataset_ = GDALDataset::Open(copy.c_str(), GDAL_OF_VECTOR | GDAL_OF_UPDATE, drivers, nullptr, nullptr);
    if (dataset_ != nullptr) return true;
    if (required)
      fail("exists, and GDAL cannot open it as a " + driver_ + " data source to update" + capture.detail() +
           "; remove it, or write elsewhere");
    fs::remove(copy, ec);
    capture.clear();
    return false;
  }

  // What identifies a version of a file: device, inode, size, modification time.
  static std::vector<long long> file_state(const fs::path& p) {
    struct stat st {};
    if (::stat(p.c_str(), &st) != 0) return {};
    return {static_cast<long long>(st.st_dev), static_cast<long long>(st.st_ino), static_cast<long long>(st.st_size),
            static_cast<long long>(st.st_mtim.tv_sec), static_cast<long long>(st.st_mtim.tv_nsec)};
  }

  // In update mode, the layer of the same name that the data source had: deleted with
  // overwrite, else refused.
  void replace_existing_layer(const std::string& name) {
    ErrorCapture capture;
    for (int i = 0; i < dataset_->GetLayerCount(); ++i) {
      OGRLayer* layer = dataset_->GetLayer(i);
      if (layer == nullptr || !ascii_iequals(layer->GetName(), name)) continue;
      if (!options_.overwrite)
        fail("has a layer '" + name + "'; use --overwrite to replace it (the other layers are kept), or --nln to name the new one");
      if (dataset_->DeleteLayer(i) != OGRERR_NONE) fail("cannot delete its layer '" + name + "'" + capture.detail());
      return;
    }
  }

  void create(GDALDriver* driver, const std::string& filename, const std::vector<Field>& schema,
              const WriterOptions& options) {
    ErrorCapture capture;
    if (dataset_ == nullptr) {
      const std::string temp_file = (temp_dir_ / filename).string();
      CPLStringList dsco;
      for (const std::string& o : options.dataset_options) dsco.AddString(o.c_str());
      dataset_ = driver->Create(temp_file.c_str(), 0, 0, 0, GDT_Unknown, dsco.List());
      if (dataset_ == nullptr) fail("cannot create" + capture.detail());
    }
    if (updating_) replace_existing_layer(options.layer);

    OGRSpatialReference srs;
    srs.importFromEPSG(4326);
    srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    CPLStringList lco;
    const bool shapefile = ascii_iequals(driver_, "ESRI Shapefile");
    if (ascii_iequals(driver_, "CSV")) lco.SetNameValue("GEOMETRY", "AS_WKT");
    if (shapefile) {
      lco.SetNameValue("ENCODING", "UTF-8");  // writes a .cpg; our strings are UTF-8
      lco.SetNameValue("RESIZE", "YES");      // string widths shrunk to the longest value
    }
    for (const std::string& o : options.layer_options) {  // the user's, over geovor's own
      const std::size_t eq = o.find('=');
      lco.SetNameValue(o.substr(0, eq).c_str(), o.substr(eq + 1).c_str());
    }
    const OGRwkbGeometryType gtype = geometry_type_ == GeometryType::Point ? wkbPoint
                                     : geometry_type_ == GeometryType::MultiLineString
                                         ? wkbMultiLineString
                                         : wkbMultiPolygon;
    layer_ = dataset_->CreateLayer(options.layer.c_str(), &srs, gtype, lco.List());
    if (layer_ == nullptr) fail("cannot create layer '" + options.layer + "'" + capture.detail());
    written_layers_.push_back(options.layer);

    const std::vector<std::string> names =
        shapefile ? shapefile_field_names(schema) : [&] {
          std::vector<std::string> n;
          for (const Field& f : schema) n.push_back(f.name);
          return n;
        }();
    define_fields(schema, names, shapefile);
    if (!transaction_ && dataset_->TestCapability(ODsCTransactions)) {
      if (dataset_->StartTransaction() != OGRERR_NONE) fail("cannot start a transaction" + capture.detail());
      transaction_ = true;
    }
    feature_.reset(OGRFeature::CreateFeature(layer_->GetLayerDefn()));
    if (capture.failed()) fail("cannot create" + capture.detail());
  }

  // The fields in the driver's own types, or the nearest it has (as ogr2ogr maps them: Integer
  // to Integer64 to Real, Date and DateTime to String), JSON lists with the JSON subtype.
  void define_fields(const std::vector<Field>& schema, const std::vector<std::string>& names, bool shapefile) {
    ErrorCapture capture;
    const GDALDriver* driver = dataset_->GetDriver();
    if (shapefile || ascii_iequals(driver_, "MapInfo File")) max_bytes_ = kShapefileMaxBytes;
    const char* listed = driver ? const_cast<GDALDriver*>(driver)->GetMetadataItem(GDAL_DMD_CREATIONFIELDDATATYPES) : nullptr;
    const CPLStringList types(CSLTokenizeString(listed ? listed : ""));
    auto has = [&](const char* type) { return listed == nullptr || types.FindString(type) >= 0; };
    for (std::size_t i = 0; i < schema.size(); ++i) {
      FieldType type = schema[i].type;
      if (type == FieldType::Integer && !has("Integer")) type = FieldType::Integer64;
      if (type == FieldType::Integer64 && !has("Integer64")) type = has("Real") ? FieldType::Real : FieldType::String;
      if (type == FieldType::DateTime && !has("DateTime")) type = FieldType::String;
      if (type == FieldType::Date && !has("Date")) type = FieldType::String;
      if (type == FieldType::Real && !has("Real")) type = FieldType::String;
      const OGRFieldType ogr_type = type == FieldType::Integer     ? OFTInteger
                                    : type == FieldType::Integer64 ? OFTInteger64
                                    : type == FieldType::Real      ? OFTReal
                                    : type == FieldType::Date      ? OFTDate
                                    : type == FieldType::DateTime  ? OFTDateTime
                                                                   : OFTString;
      if (names[i] != schema[i].name)  // told as GDAL tells it when it launders a name itself
        CPLError(CE_Warning, CPLE_AppDefined, "Normalized/laundered field name: '%s' to '%s'", schema[i].name.c_str(),
                 names[i].c_str());
      OGRFieldDefn defn(names[i].c_str(), ogr_type);
      if (schema[i].json && ogr_type == OFTString) defn.SetSubType(OFSTJSON);
      // DBF fields have a fixed width: give room for the widest values (RESIZE=YES shrinks
      // them to the data). GDAL's defaults lose values: Integer64 (18 characters) cannot hold
      // 19 digits, Real (24.15) nothing from 1e8 on (areas in m2!).
      if (shapefile && ogr_type == OFTString) defn.SetWidth(kShapefileMaxBytes);
      if (shapefile && ogr_type == OFTInteger) defn.SetWidth(11);
      if (shapefile && ogr_type == OFTInteger64) defn.SetWidth(20);
      if (shapefile && ogr_type == OFTReal) {
        defn.SetWidth(33);  // up to 1e17 with 15 decimals
        defn.SetPrecision(15);
      }
      if (layer_->CreateField(&defn, TRUE) != OGRERR_NONE) {
        // A driver without attribute fields (DXF, DGN) or without this type: the format, not
        // the disk, is at fault, and nothing was written yet.
        const std::string why = capture.detail();
        {
          ErrorCapture ignore;
          discard();
        }
        failed_ = true;
        throw Error(ErrorCode::InvalidArgument,
                    path_ + ": format " + driver_ + " cannot hold the field '" + schema[i].name + "' (" +
                        to_string(type) + ")" + why + "; " + field_refusal_fix(schema[i].name));
      }
      // Drivers may rename a field (laundering); it is the last one created either way.
      field_index_.push_back(layer_->GetLayerDefn()->GetFieldCount() - 1);
      written_types_.push_back(type);
      field_names_.push_back(schema[i].name);
    }
  }

  // What to do about a field the driver refused: an --lco FID=NAME naming it made it the
  // driver's integer feature id column; otherwise another format.
  std::string field_refusal_fix(const std::string& name) const {
    for (const std::string& o : options_.layer_options) {
      const std::size_t eq = o.find('=');
      if (ascii_iequals(o.substr(0, eq), "FID") && ascii_iequals(o.substr(eq + 1), name))
        return "--lco " + o + " makes '" + name + "' the layer's feature id column, which holds integer feature ids only: "
               "leave out that option or name another column (FID=fid is " + driver_ + "'s default)";
    }
    return "write " + other_formats(driver_);
  }

  // Each value into feature_ as its field's written type; a value that type or the driver cannot
  // hold whole is refused (Error(BadData), the output removed): never cut or rounded.
  void set_values(std::span<const FieldValue> values, const std::string& feature) {
    OGRFeature& f = *feature_;
    auto refuse = [&](std::size_t i, const std::string& why) {
      failed_ = true;
      {
        ErrorCapture ignore;
        discard();
      }
      throw Error(ErrorCode::BadData, path_ + ": " + feature + ", field '" + field_names_[i] + "': " + why);
    };
    for (std::size_t i = 0; i < values.size(); ++i) {
      const int index = field_index_[i];
      const FieldValue& v = values[i];
      const FieldType type = written_types_[i];
      if (const auto* n = std::get_if<std::int64_t>(&v)) {
        if (type == FieldType::Integer && (*n < INT32_MIN || *n > INT32_MAX))
          refuse(i, std::to_string(*n) + " does not fit a 32-bit Integer field");
        if (type == FieldType::Real && (*n > (std::int64_t{1} << 53) || *n < -(std::int64_t{1} << 53)))
          refuse(i, std::to_string(*n) + " needs an Integer64 field, which " + driver_ +
                        " does not have (its Real would round it); write " + other_formats(driver_));
        f.SetField(index, static_cast<GIntBig>(*n));
      } else if (const auto* d = std::get_if<double>(&v)) {
        f.SetField(index, *d);
      } else if (const auto* s = std::get_if<std::string>(&v)) {
        if (max_bytes_ > 0 && s->size() > max_bytes_)
          refuse(i, std::to_string(s->size()) + " bytes, but a field of format " + driver_ + " holds at most " +
                        std::to_string(max_bytes_) + " bytes (the value would be cut); write GeoPackage, FlatGeobuf "
                        "or GeoJSON, which hold values of any length");
        f.SetField(index, s->c_str());
      } else {
        f.SetFieldNull(index);
      }
    }
  }

  OGRGeometry* to_ogr(const Geometry& g) {
    if (const auto* p = std::get_if<LonLat>(&g)) return is_null_point(*p) ? nullptr : new OGRPoint(p->lon_deg, p->lat_deg);
    auto fill = [&](OGRSimpleCurve& curve, const std::vector<LonLat>& ps) {
      raw_.resize(ps.size());
      for (std::size_t i = 0; i < ps.size(); ++i) raw_[i] = OGRRawPoint(ps[i].lon_deg, ps[i].lat_deg);
      curve.setPoints(static_cast<int>(raw_.size()), raw_.data());
    };
    if (const auto* lines = std::get_if<MultiLineString>(&g)) {
      auto* mls = new OGRMultiLineString;
      for (const LineString& line : *lines) {
        auto* ls = new OGRLineString;
        fill(*ls, line);
        mls->addGeometryDirectly(ls);
      }
      return mls;
    }
    auto* mp = new OGRMultiPolygon;
    for (const Polygon& poly : std::get<MultiPolygon>(g)) {
      auto* op = new OGRPolygon;
      auto* ext = new OGRLinearRing;
      fill(*ext, poly.exterior);
      op->addRingDirectly(ext);
      for (const Ring& hole : poly.holes) {
        auto* r = new OGRLinearRing;
        fill(*r, hole);
        op->addRingDirectly(r);
      }
      mp->addGeometryDirectly(op);
    }
    return mp;
  }

  // Renames the files of the temporary directory into place: the sidecars, then the main file.
  void move_into_place() {
    const fs::path target(path_);
    const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
    const std::string filename = target.filename().string();
    const std::string stem = target.stem().string();
    std::vector<std::string> produced;
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(temp_dir_, ec)) {
      const std::string name = entry.path().filename().string();
      // NAME itself, and STEM.EXT sidecars; anything else is the driver's scratch.
      const bool sidecar = name.size() > stem.size() + 1 && name.compare(0, stem.size(), stem) == 0 &&
                           name[stem.size()] == '.' &&
                           name.find('.', stem.size() + 1) == std::string::npos;
      if (name == filename || sidecar) produced.push_back(name);
    }
    if (ec) fail("cannot list " + temp_dir_.string() + ": " + ec.message());
    if (std::find(produced.begin(), produced.end(), filename) == produced.end()) {
      fail("the " + driver_ + " driver did not write " + filename);
    }
    // An updated data source replaces the version it was copied from, and no other.
    if (updating_ && file_state(target) != original_)
      fail("changed while geovor was updating it; not replaced (its new layer is lost, its content is as the other program left it)");
    for (const std::string& name : produced) {
      const fs::path dest = dir / name;
      if (fs::exists(fs::symlink_status(dest, ec)) && !overwrite_ok(dest)) {
        fail(output_exists(dest.string()));
      }
    }
    // A replaced output must not keep sidecars of its previous version (an old .qix or .cpg).
    for (const std::string& ext : stale_sidecars(driver_)) {
      fs::path old = target;
      old.replace_extension(ext);
      const std::string name = old.filename().string();
      if (std::find(produced.begin(), produced.end(), name) == produced.end()) {
        fs::remove(old, ec);
      }
    }
    std::stable_partition(produced.begin(), produced.end(),
                          [&](const std::string& n) { return n != filename; });
    std::vector<fs::path> moved;
    for (const std::string& name : produced) {
      // Never over a file that appeared meanwhile, unless overwriting.
      const int err = rename_into_place((temp_dir_ / name).string(), (dir / name).string(), overwrite_ || updating_);
      if (err != 0) {
        for (const fs::path& p : moved) fs::remove(p, ec);
        if (err == EEXIST) fail(output_exists((dir / name).string()));
        fail("cannot rename " + (temp_dir_ / name).string() + " to " + (dir / name).string() +
             ": " + std::strerror(err));
      }
      moved.push_back(dir / name);
    }
    fs::remove_all(temp_dir_, ec);
    temp_.release();
    temp_dir_.clear();
  }

  // GDAL's message; when a driver failed without one (the CSV driver on a full disk), the
  // system's reason, errno having been cleared before the call.
  static std::string detail(const ErrorCapture& capture) {
    if (capture.failed()) return capture.detail();
    return errno != 0 ? std::string(" (") + std::strerror(errno) + ")" : "";
  }

  bool overwrite_ok(const fs::path& dest) const {
    std::error_code ec;
    return (overwrite_ || updating_) && !fs::is_directory(fs::status(dest, ec));
  }

  // Closes without committing and removes every temporary file; the target is untouched.
  void discard() noexcept {
    feature_.reset();
    if (dataset_ != nullptr) {
      if (transaction_) dataset_->RollbackTransaction();
      GDALClose(GDALDataset::ToHandle(std::exchange(dataset_, nullptr)));
    }
    transaction_ = false;
    layer_ = nullptr;
    temp_.discard();  // the directory and everything in it
    temp_dir_.clear();
  }

  [[noreturn]] void fail(const std::string& what) {
    failed_ = true;
    {
      ErrorCapture ignore;
      discard();
    }
    throw Error(ErrorCode::Io, path_ + ": " + what);
  }

  std::string path_;
  std::string driver_;
  GeometryType geometry_type_;
  std::size_t field_count_;
  bool overwrite_ = false;
  WriterOptions options_;
  bool layered_ = false;   // the driver holds several layers
  bool updating_ = false;  // an existing data source, copied and updated (open_copy)
  std::vector<long long> original_;  // file_state() of the data source copied
  std::vector<std::string> written_layers_;
  TemporaryOutput temp_;
  fs::path temp_dir_;  // temp_'s path
  GDALDataset* dataset_ = nullptr;
  OGRLayer* layer_ = nullptr;
  std::unique_ptr<OGRFeature> feature_;
  std::vector<int> field_index_;
  std::vector<FieldType> written_types_;  // each field's type in the file
  std::vector<std::string> field_names_;  // as in the schema, for messages
  std::size_t max_bytes_ = 0;             // the longest text a field holds; 0: no limit
  std::vector<OGRRawPoint> raw_;
  bool transaction_ = false;
  std::uint64_t count_ = 0;
  bool finished_ = false;
  bool failed_ = false;
};

}  // namespace

void register_gdal() {
  static std::once_flag once;
  std::call_once(once, [] { GDALAllRegister(); });
}

ErrorCapture::ErrorCapture() {
  CPLPushErrorHandlerEx(capture_handler, this);
  CPLSetCurrentErrorHandlerCatchDebug(FALSE);
}

ErrorCapture::~ErrorCapture() { CPLPopErrorHandler(); }

void ErrorCapture::record(int error_class, const char* message) {
  if (error_class < CE_Failure || message == nullptr) return;
  constexpr std::size_t kMax = 400;
  if (message_.size() >= kMax) return;
  std::string_view text(message);
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r' || text.back() == ' ')) text.remove_suffix(1);
  if (text.empty()) return;
  if (!message_.empty()) message_ += "; ";
  message_ += text;  // without GDAL's closing newline (messages escape control characters)
  if (message_.size() > kMax) message_ = message_.substr(0, kMax) + "...";
}

std::string driver_for_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  if (ext.size() < 2) return "";
  ext = ascii_lower(ext.substr(1));
  register_gdal();
  GDALDriverManager* manager = GetGDALDriverManager();
  std::vector<std::string> found;
  for (int i = 0; i < manager->GetDriverCount(); ++i) {
    GDALDriver* d = manager->GetDriver(i);
    if (d->GetMetadataItem(GDAL_DCAP_VECTOR) == nullptr ||
        d->GetMetadataItem(GDAL_DCAP_CREATE) == nullptr) {
      continue;
    }
    const char* exts = d->GetMetadataItem(GDAL_DMD_EXTENSIONS);
    if (exts == nullptr) continue;
    const CPLStringList list(CSLTokenizeString(exts));
    for (int k = 0; k < list.size(); ++k) {
      if (ascii_lower(list[k]) == ext) {
        found.emplace_back(d->GetDescription());
        break;
      }
    }
  }
  if (found.size() > 1) {
    std::string names;
    for (const auto& n : found) names += (names.empty() ? "" : ", ") + n;
    throw Error(ErrorCode::InvalidArgument, path + ": several formats write ." + ext + " files (" +
                                                names + "); choose one with --format");
  }
  return found.empty() ? "" : found.front();
}

std::string format_refusal(const std::string& name, GeometryType geometry_type, const WriterOptions& options) {
  register_gdal();
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName(name.c_str());
  if (driver == nullptr || driver->GetMetadataItem(GDAL_DCAP_VECTOR) == nullptr ||
      driver->GetMetadataItem(GDAL_DCAP_CREATE) == nullptr)
    return "unknown output format '" + name + "': not a GDAL vector driver that can create files (see ogrinfo --formats)";
  const std::string d = driver->GetDescription();
  const std::string instead = "write " + other_formats(d);
  auto yes = [](const std::vector<std::string>& list, const char* key) {
    for (const std::string& o : list) {
      const std::size_t eq = o.find('=');
      if (eq != std::string::npos && ascii_iequals(o.substr(0, eq), key) && CPLTestBool(o.substr(eq + 1).c_str())) return true;
    }
    return false;
  };
  if (const char* nonspatial = driver->GetMetadataItem(GDAL_DCAP_NONSPATIAL); nonspatial && CPLTestBool(nonspatial))
    // Spreadsheets (ODS, XLSX) would drop every geometry without a word.
    return "format " + d + " stores no geometry, so the features' geometry would be lost; "
           "write CSV (geometry as WKT, which spreadsheets open) or GeoPackage";
  // Neither field creation nor field types: the driver writes only a schema of its own (DXF, DGN, S57).
  if (driver->GetMetadataItem(GDAL_DCAP_CREATE_FIELD) == nullptr &&
      driver->GetMetadataItem(GDAL_DMD_CREATIONFIELDDATATYPES) == nullptr)
    return "format " + d + " holds no attribute fields of the writer's choosing (only its own schema), so every field "
           "would be lost; " + instead;
  // What GDAL's metadata does not say: fixed schemas and geometry types (docs/user-guide.md lists them).
  if (ascii_iequals(d, "GPX")) {
    if (geometry_type == GeometryType::MultiPolygon)
      return "format GPX holds points (waypoints) and lines (routes, tracks), no polygons; " + instead;
    if (!yes(options.dataset_options, "GPX_USE_EXTENSIONS"))
      return "format GPX holds only its own fields (name, ele, time, ...); --dsco GPX_USE_EXTENSIONS=YES writes the "
             "others as <extensions>, or " + instead;
  }
  if (ascii_iequals(d, "GeoRSS") && !yes(options.dataset_options, "USE_EXTENSIONS"))
    return "format GeoRSS holds only the elements of RSS (title, description, ...); --dsco USE_EXTENSIONS=YES writes "
           "the other fields as extensions, or " + instead;
  if (ascii_iequals(d, "PCIDSK") && geometry_type != GeometryType::Point)
    return "format PCIDSK cannot hold geovor's layers: it drops multi-part geometries without a word, and every "
           "polygon and line geovor writes is one; " + instead;
  static constexpr std::pair<std::string_view, std::string_view> kFixed[] = {
      {"VDV", "VDV-451 tables hold no geometry"},
      {"Interlis 1", "it writes the classes of an INTERLIS model, not a schema of the writer's choosing"},
      {"PDS4", "it writes its tables into a directory beside the label, which geovor does not move into place"},
      {"WAsP", "a WAsP map holds lines of elevation or roughness only"},
      {"Selafin", "a Selafin (TELEMAC) mesh holds points with Real values only"},
      {"FITS", "FITS tables hold no geometry"},
      {"Geoconcept", "it has no Integer64 fields (geovor's indices and counts are)"},
      {"MVT", "vector tiles snap coordinates to each zoom level's grid and cut features at tile edges, so the "
              "geometry would not be written as computed (nor stay valid)"},
      {"MBTiles", "vector tiles snap coordinates to each zoom level's grid and cut features at tile edges, so the "
                  "geometry would not be written as computed (nor stay valid)"},
  };
  for (const auto& [fixed, why] : kFixed)
    if (ascii_iequals(d, fixed))
      return "format " + d + " cannot hold geovor's layers: " + std::string(why) + "; " + instead;
  return "";
}

bool driver_holds_layers(const std::string& name) {
  register_gdal();
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName(name.c_str());
  return driver != nullptr && driver->GetMetadataItem(GDAL_DCAP_MULTIPLE_VECTOR_LAYERS) != nullptr;
}

std::vector<std::string> shapefile_field_names(const std::vector<Field>& schema) {
  constexpr std::size_t kMaxBytes = 10;
  // The first `max_bytes` bytes of `name`, not cutting a UTF-8 sequence.
  auto cut = [](const std::string& name, std::size_t max_bytes) {
    if (name.size() <= max_bytes) return name;
    std::size_t n = max_bytes;
    while (n > 0 && (static_cast<unsigned char>(name[n]) & 0xC0) == 0x80) --n;
    return name.substr(0, n);
  };
  std::set<std::string> used;  // lower case
  std::vector<std::string> out;
  for (const Field& field : schema) {
    std::string name = cut(field.name, kMaxBytes);
    for (int k = 1; used.count(ascii_lower(name)) != 0; ++k) {
      std::string suffix(1, '_');
      suffix += std::to_string(k);
      name = cut(field.name, kMaxBytes - suffix.size()) + suffix;
    }
    used.insert(ascii_lower(name));
    out.push_back(name);
  }
  return out;
}

std::unique_ptr<FeatureWriter> open_gdal_writer(const std::string& path, const std::string& driver,
                                                GeometryType geometry_type,
                                                const std::vector<Field>& schema,
                                                const WriterOptions& options) {
  return std::make_unique<GdalWriter>(path, driver, geometry_type, schema, options);
}

}  // namespace geovor::gdal_detail
