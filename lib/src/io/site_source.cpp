// read_sites: which reader a path calls for. Kept apart from the OGR reader, which alone needs
// GDAL: the geovor tool reads CSV without loading GDAL at all.
#include <filesystem>
#include <string>

#include "geovor/io/ogr_site_reader.hpp"

namespace geovor {

bool is_csv_site_path(const std::string& path) {
  if (path == "-") return true;
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext)
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  return ext == ".csv" || ext == ".txt";
}

SiteTable read_sites(const std::string& path, const SiteReaderOptions& options) {
  return is_csv_site_path(path) ? read_sites_csv_file(path, options) : read_sites_ogr(path, options);
}

}  // namespace geovor
