// cells_to_gpkg SITES.csv CELLS.gpkg: the Voronoi cell of every site of a CSV, with the rows'
// attributes, areas and neighbours, written to a GeoPackage (what `geovor cells` does).
#include <cstdio>
#include <exception>
#include <vector>

#include <geovor/delaunay/spherical_delaunay.hpp>
#include <geovor/geo/site_reader.hpp>
#include <geovor/layers/cell_layer.hpp>

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: cells_to_gpkg SITES.csv CELLS.gpkg\n");
    return 2;
  }
  try {
    const geovor::SiteTable table = geovor::read_sites_csv_file(argv[1]);
    for (const geovor::RejectedRow& r : table.rejected)
      std::fprintf(stderr, "%s: row %llu: %s\n", argv[1], static_cast<unsigned long long>(r.row), r.reason.c_str());
    std::vector<geovor::Vec3> points;
    for (const geovor::InputSite& s : table.sites) points.push_back(s.unit);
    geovor::BuildReport report;  // which row went into which site (merged duplicates)
    const geovor::SphericalDelaunay dt = geovor::SphericalDelaunay::build(points, {}, &report);

    const auto writer = geovor::open_cell_layer_writer(argv[2], table, {});
    const geovor::CellLayerReport cells = geovor::write_cell_layer(*writer, table, report, dt);
    writer->finish();  // the file appears complete, or not at all
    std::printf("%zu cells written to %s (%zu empty: not valid as stored)\n", cells.cells_written, argv[2],
                cells.unwritten.size());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cells_to_gpkg: %s\n", e.what());
    return 1;
  }
}
