/// \file gdal_writer.hpp
/// \brief Private: the GDAL/OGR writer behind open_feature_writer() for every format other than
/// GeoJSON/GeoJSONSeq, and the GDAL helpers the OGR site reader shares.
///
/// This header includes no GDAL header (feature_writer.cpp includes it); only gdal_writer.cpp
/// and gdal_site_reader.cpp include GDAL.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "geovor/io/feature_writer.hpp"

namespace geovor::gdal_detail {

/// GDALAllRegister(), once per process (thread-safe).
void register_gdal();

/// Collects the GDAL errors (CE_Failure, CE_Fatal) raised on this thread while it is alive,
/// instead of letting GDAL print them; warnings still go to GDAL's default handler (stderr),
/// debug messages are dropped. Instances nest (GDAL keeps a per-thread handler stack).
class ErrorCapture {
 public:
  ErrorCapture();
  ~ErrorCapture();
  ErrorCapture(const ErrorCapture&) = delete;
  ErrorCapture& operator=(const ErrorCapture&) = delete;
  bool failed() const { return !message_.empty(); }
  /// The failure messages, "; "-separated (at most a few hundred characters), or "".
  const std::string& message() const { return message_; }
  /// " (GDAL: message)" or "" when nothing was captured.
  std::string detail() const { return failed() ? " (GDAL: " + message_ + ")" : ""; }
  void record(int error_class, const char* message);
  /// Forgets what was captured (after an error that has been handled).
  void clear() { message_.clear(); }

 private:
  std::string message_;
};

/// The one GDAL vector driver that can create files with `path`'s extension (from the drivers'
/// DMD_EXTENSIONS), or "" when none does.
/// @exception Error(InvalidArgument) naming the candidates when several drivers do.
std::string driver_for_extension(const std::string& path);

/// Why the GDAL driver named `driver` cannot hold a geovor layer of `geometry_type` with its
/// fields, or "" when it can: an unknown driver or one that cannot create vector files; a driver
/// without geometry (DCAP_NONSPATIAL: ODS, XLSX); one without fields of the writer's choosing
/// (neither DCAP_CREATE_FIELD nor DMD_CREATIONFIELDDATATYPES: DXF, DGN, S57); and what the
/// metadata does not tell: GPX (no polygons; fields only with GPX_USE_EXTENSIONS=YES), GeoRSS
/// (fields only with USE_EXTENSIONS=YES), PCIDSK (no multi-part geometry: points only), WAsP,
/// Selafin, FITS, Geoconcept, MVT, MBTiles, VDV, Interlis 1, PDS4. The reason names a format
/// that works.
std::string format_refusal(const std::string& driver, GeometryType geometry_type, const WriterOptions& options);

/// Whether the GDAL driver named `driver` holds several vector layers in one data source
/// (DCAP_MULTIPLE_VECTOR_LAYERS); false for a driver GDAL does not know.
bool driver_holds_layers(const std::string& driver);

/// Field names as the Shapefile format allows them: at most 10 bytes (cut at a UTF-8 character
/// boundary), unique case-insensitively. A name that collides once cut gets a suffix "_1", "_2",
/// ... in schema order, its stem shortened to keep 10 bytes: "population_2020" ->
/// "population", "population_2021" -> "populati_1". Names that fit are kept as they are.
std::vector<std::string> shapefile_field_names(const std::vector<Field>& schema);

/// Opens a writer through the GDAL vector driver named `driver` (any driver with DCAP_VECTOR
/// and DCAP_CREATE). The dataset is created in a private temporary directory
/// ".NAME.tmp-PID-N/" next to `path`, under its final file name; finish() closes it and renames
/// every file it produced (NAME and its sidecars STEM.*, e.g. .shx/.dbf/.prj/.cpg) into place,
/// the main file last. Any failure, or destruction without finish(), removes the directory.
/// Updating an existing multi-layer data source (WriterOptions::update, or overwrite of one
/// layer), the file is copied into that directory, opened there for update, and renamed over
/// the original by finish() if the original is unchanged since the copy.
/// @exception Error(InvalidArgument) unknown driver or "-" as path; Error(Io) as
///   open_feature_writer().
std::unique_ptr<FeatureWriter> open_gdal_writer(const std::string& path, const std::string& driver,
                                                GeometryType geometry_type,
                                                const std::vector<Field>& schema,
                                                const WriterOptions& options);

}  // namespace geovor::gdal_detail
