// Uses an installed geovor: the Delaunay triangulation of the 8 corners of a cube inscribed in
// the unit sphere has 12 triangles (2n - 4) and is valid, and its cell layer (the products
// module) has 8 cells, all written. Exit 0 iff so.
#include <cmath>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "geovor/core/types.hpp"
#include "geovor/delaunay/spherical_delaunay.hpp"
#include "geovor/layers/cell_layer.hpp"

int main() {
  try {
    const double c = 1.0 / std::sqrt(3.0);
    std::vector<geovor::Vec3> corners;
    for (double x : {-c, c})
      for (double y : {-c, c})
        for (double z : {-c, c}) corners.push_back({x, y, z});

    geovor::BuildReport report;
    const auto dt = geovor::SphericalDelaunay::build(corners, {}, &report);
    const auto validation = dt.validate();
    std::printf("sites: %zu\ntriangles: %zu\nvalid: %s\n", dt.num_sites(), dt.num_triangles(),
                validation.ok() ? "yes" : "no");
    for (const auto& error : validation.errors) std::printf("error: %s\n", error.c_str());

    geovor::SiteTable table;
    for (const geovor::Vec3& p : corners) {
      geovor::InputSite row;
      row.id = std::to_string(table.sites.size());
      row.unit = p;
      table.sites.push_back(row);
    }
    geovor::WriterOptions options;
    options.format = "GeoJSON";  // /dev/null has no extension
    const auto writer = geovor::open_cell_layer_writer("/dev/null", table, options);
    const geovor::CellLayerReport cells = geovor::write_cell_layer(*writer, table, report, dt);
    writer->finish();
    std::printf("cells: %zu\nunwritten: %zu\n", cells.cells_written, cells.unwritten.size());
    return dt.num_triangles() == 12 && validation.ok() && cells.cells_written == 8 && cells.unwritten.empty() ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "geovor_consumer: %s\n", e.what());
    return 1;
  }
}
