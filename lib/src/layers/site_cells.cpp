#include "geovor/layers/site_cells.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>

#include "geovor/layers/row_accounting.hpp"
#include "geovor/layers/row_report.hpp"

namespace geovor {

SiteCells::SiteCells(const SiteInput& input, const std::string& output, const SiteCellsOptions& options)
    : input_(input) {
  if (!options.report_path.empty())
    report_file_ = std::make_unique<OutputFile>(options.report_path, options.file.writer.overwrite);
  input_.reader.threads = options.threads;
  geojson_ = output_kind(output, options.file.writer.format) != OutputKind::Gdal;
  staged_.emplace(input_, options.threads != 1, [this](const SiteTable& table) {
    if (geojson_) ids_ = make_cell_id_texts(table, 1);
  });
  // A value not of its declared type fails the rows' stage: before an old output is removed below.
  if (!input_.reader.field_types.empty()) staged_->table();
  remove_old_output(output, options.file);
  dt_.emplace(build_sites(staged_->positions(), staged_->lifts(), input_, build_));
  removal_.wait();
  // The diagram while the rows' strings and ids are finished on the other core.
  diagram_.emplace(*dt_, options.threads);
  write(output, options);
}

void SiteCells::remove_old_output(const std::string& output, const CellFileOptions& file) {
  struct stat st;
  if (file.writer.overwrite && output != "-" && geojson_ && ::lstat(output.c_str(), &st) == 0 && S_ISREG(st.st_mode))
    removal_.run([path = output] { ::unlink(path.c_str()); });
}

void SiteCells::write(const std::string& output, const SiteCellsOptions& options) {
  const SiteTable& table = staged_->table();
  CellFileOptions file = options.file;
  if (staged_->ids_repeat()) file.writer.id_field = "site_index";  // feature ids stay unique
  file.layer.threads = options.threads;
  file.layer.id_texts = &ids_;
  file.layer.diagram = &*diagram_;
  list_build(input_, table, build_);  // merged rows stay in the cells' ids and the report
  const std::string at = geojson_ ? "at " + file.precision_name + " " + std::to_string(file.writer.precision)
                                  : "at full precision";
  cells_ = write_cell_file(output, table, build_, *dt_, file, [&](const CellLayerReport& cells) {
    if (!report_file_) return;
    write_row_report(report_file_->get(), table, build_, cells.unwritten, at);
    report_file_->flush();  // a full disk fails here, before the cells are renamed into place
  });
  if (report_file_) report_file_->commit();
  if (!file.quiet && file.log != nullptr)
    std::fprintf(file.log, "%s; %zu cells written to %s\n", row_counts(table, dt_->num_sites(), build_.merges.size()).c_str(),
                 cells_.cells_written, output.c_str());
}

}  // namespace geovor
