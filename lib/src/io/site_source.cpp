// read_sites: which reader a path calls for. Kept apart from the OGR reader, which alone needs
// GDAL: the geovor tool reads CSV without loading GDAL at all.
#include <iconv.h>
#include <sys/stat.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <string>
#include <string_view>

#include "geovor/core/ascii.hpp"
#include "geovor/io/ogr_site_reader.hpp"

namespace geovor {
namespace {

// Extensions of delimited text, read by the CSV reader whatever their content.
constexpr std::array<std::string_view, 5> kTextExtensions = {".csv", ".tsv", ".txt", ".dat", ".psv"};
// Extensions of formats GDAL reads: never sniffed as text (a GeoJSON or KML file is text too).
constexpr std::array<std::string_view, 32> kOgrExtensions = {
    ".gpkg", ".geojson", ".json", ".geojsonl", ".geojsons", ".shp", ".dbf", ".shx", ".fgb", ".gml", ".kml",
    ".kmz", ".gpx", ".tab", ".mif", ".sqlite", ".db", ".gdb", ".xlsx", ".xls", ".ods", ".zip", ".gz",
    ".vrt", ".osm", ".pbf", ".parquet", ".arrow", ".feather", ".mbtiles", ".pmtiles", ".xml"};

// `head` decoded from `encoding` into `out` as far as it goes (the last character may be cut).
std::string_view decode_head(const char* head, std::size_t n, const std::string& encoding, std::string& out) {
  iconv_t cd = iconv_open("UTF-8", encoding.c_str());
  if (cd == reinterpret_cast<iconv_t>(-1)) return {head, n};  // the reader names a bad encoding
  out.assign(4 * n + 16, '\0');
  char* in = const_cast<char*>(head);
  std::size_t in_left = n, out_left = out.size();
  char* o = out.data();
  iconv(cd, &in, &in_left, &o, &out_left);
  iconv_close(cd);
  return {out.data(), out.size() - out_left};
}

// Whether the file's first bytes, decoded from `encoding` (UTF-8 when empty), are delimited text:
// no NUL byte, not JSON or XML, and a first line holding a delimiter (',', ';', TAB or '|').
bool looks_like_delimited_text(const std::string& path, const std::string& encoding) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) return false;
  char buf[4096];
  const std::size_t n = std::fread(buf, 1, sizeof buf, f);
  std::fclose(f);
  std::string decoded;
  const std::string e = ascii_lower(encoding);
  // UTF-16 text holds NUL bytes: the head is judged as the reader will see it.
  const std::string_view text = e.empty() || e == "utf-8" || e == "utf8" ? std::string_view(buf, n)
                                                                        : decode_head(buf, n, encoding, decoded);
  if (text.empty() || text.find('\0') != std::string_view::npos) return false;
  std::size_t first = text.starts_with("\xEF\xBB\xBF") ? 3 : 0;
  first = text.find_first_not_of(" \t\r\n", first);
  if (first == std::string_view::npos || std::string_view("{[<").find(text[first]) != std::string_view::npos) return false;
  const std::string_view line = text.substr(first, text.find_first_of("\r\n", first) - first);
  return line.find_first_of(",;\t|") != std::string_view::npos;
}

}  // namespace

bool is_stream_path(const std::string& path) {
  if (path == "-") return true;
  if (path.starts_with("/vsi")) return false;
  struct stat st;
  return ::stat(path.c_str(), &st) == 0 && (S_ISFIFO(st.st_mode) || S_ISCHR(st.st_mode) || S_ISSOCK(st.st_mode));
}

bool is_csv_site_path(const std::string& path, const std::string& encoding) {
  // A pipe, FIFO or device can be read only once, so it cannot be sniffed nor handed to GDAL
  // (which opens a source several times): it is delimited text, its head checked once read.
  if (is_stream_path(path)) return true;
  const std::string ext = ascii_lower(std::filesystem::path(path).extension().string());
  // GDAL's virtual file systems and connection strings (PG:..., /vsizip/...) are OGR's.
  if (path.starts_with("/vsi")) return false;
  if (std::find(kTextExtensions.begin(), kTextExtensions.end(), ext) != kTextExtensions.end()) return true;
  if (path.find(':') != std::string::npos) return false;
  if (std::find(kOgrExtensions.begin(), kOgrExtensions.end(), ext) != kOgrExtensions.end()) return false;
  std::error_code ec;
  return std::filesystem::is_regular_file(path, ec) && looks_like_delimited_text(path, encoding);
}

SiteTable read_sites(const std::string& path, const SiteReaderOptions& options) {
  if (!is_csv_site_path(path, options.encoding)) return read_sites_ogr(path, options);
  SiteTable table = read_sites_csv_file(path, options);
  if (!options.s_srs.empty()) reproject_sites(table, options.s_srs);
  return table;
}

}  // namespace geovor
