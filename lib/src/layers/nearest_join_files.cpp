#include "geovor/layers/nearest_join_files.hpp"

#include <cerrno>
#include <cstring>
#include <memory>
#include <string_view>

#include "geovor/core/error.hpp"
#include "geovor/core/output_file.hpp"
#include "geovor/io/ogr_site_reader.hpp"

namespace geovor {
namespace {

struct FileCloser {
  void operator()(std::FILE* f) const {
    if (f != stdin) std::fclose(f);
  }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

// Runs join(sink) with the sink of files.output: CSV text into an OutputFile, or a feature writer.
template <class Join>
NearestJoinReport into_output(const NearestJoinFiles& files, Join join) {
  if (!writes_csv(files)) {
    const OpenJoinWriter open = [&](const std::vector<Field>& fields) {
      return open_feature_writer(files.output, GeometryType::Point, fields, files.writer);
    };
    return join(open);
  }
  OutputFile out(files.output, files.writer.overwrite);  // a temporary file renamed by commit()
  const std::function<void(std::string_view)> write = [&](std::string_view s) { out.write(s.data(), s.size()); };
  const NearestJoinReport report = join(write);
  out.commit();
  return report;
}

}  // namespace

bool queries_are_ogr(const NearestJoinFiles& files) {
  return !files.query_layer.empty() || (files.queries != "-" && !is_csv_site_path(files.queries));
}

bool writes_csv(const NearestJoinFiles& files) {
  return output_kind(files.output, files.writer.format, true) == OutputKind::Text;
}

std::string query_source(const NearestJoinFiles& files) { return files.queries == "-" ? "<stdin>" : files.queries; }

NearestJoinReport nearest_join_files(const SiteIndex& index, const NearestJoinFiles& files,
                                     const NearestJoinOptions& options) {
  const std::string source = query_source(files);
  const std::function<void(const MalformedQuery&)> on_malformed = [&](const MalformedQuery& m) {
    if (files.log == nullptr) return;
    if (m.line > 0)
      std::fprintf(files.log, "%s: line %llu: %s\n", source.c_str(), static_cast<unsigned long long>(m.line),
                   m.reason.c_str());
    else
      std::fprintf(files.log, "%s: %s\n", source.c_str(), m.reason.c_str());  // an OGR reason names the feature
  };
  if (queries_are_ogr(files)) {
    SiteReaderOptions reader;
    reader.lat_field = options.columns.lat_field;
    reader.lon_field = options.columns.lon_field;
    reader.id_field = options.columns.id_field;
    reader.field_types = options.query_field_types;  // over the layer's own types, checked as it is read
    const SiteTable table = read_sites_ogr(files.queries, reader, files.query_layer);
    NearestJoinOptions table_options = options;
    table_options.query_field_types.clear();  // the table has them from its reader
    return into_output(files, [&](const auto& sink) { return nearest_join(index, table, table_options, sink, on_malformed); });
  }
  File in(files.queries == "-" ? stdin : std::fopen(files.queries.c_str(), "rb"));
  if (!in) throw Error(ErrorCode::Io, files.queries + ": cannot open: " + std::strerror(errno));
  return into_output(files, [&](const auto& sink) { return nearest_join(index, in.get(), source, options, sink, on_malformed); });
}

}  // namespace geovor
