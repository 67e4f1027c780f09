#include "memory_writer.hpp"

#include <cstdint>
#include <cstring>

#include "geovor/core/error.hpp"

namespace py = pybind11;

namespace geovor::python {
namespace {

// OGC simple features WKB, little-endian.
struct Wkb {
  std::string& out;
  void header(std::uint32_t type) {
    out.push_back(1);
    u32(type);
  }
  void u32(std::uint32_t v) {
    char b[4];
    std::memcpy(b, &v, 4);  // little-endian machines only (x86-64, arm64)
    out.append(b, 4);
  }
  void point(const LonLat& p) {
    char b[16];
    std::memcpy(b, &p.lon_deg, 8);
    std::memcpy(b + 8, &p.lat_deg, 8);
    out.append(b, 16);
  }
  void points(const std::vector<LonLat>& ps) {
    u32(static_cast<std::uint32_t>(ps.size()));
    for (const LonLat& p : ps) point(p);
  }
  void operator()(const LonLat& p) {
    header(1);
    point(p);
  }
  void operator()(const MultiLineString& lines) {
    header(5);
    u32(static_cast<std::uint32_t>(lines.size()));
    for (const LineString& l : lines) {
      header(2);
      points(l);
    }
  }
  void operator()(const MultiPolygon& polygons) {
    header(6);
    u32(static_cast<std::uint32_t>(polygons.size()));
    for (const Polygon& p : polygons) {
      header(3);
      u32(static_cast<std::uint32_t>(1 + p.holes.size()));
      points(p.exterior);
      for (const Ring& h : p.holes) points(h);
    }
  }
};

}  // namespace

void MemoryFeatureWriter::write(const Geometry& geometry, std::span<const FieldValue> values) {
  if (values.size() != schema_.size())
    throw Error(ErrorCode::InvalidArgument, "feature with " + std::to_string(values.size()) + " values, schema has " +
                                                std::to_string(schema_.size()));
  std::string& wkb = wkb_.emplace_back();
  std::visit(Wkb{wkb}, geometry);
  for (std::size_t f = 0; f < values.size(); ++f) values_[f].push_back(values[f]);
}

py::dict MemoryFeatureWriter::to_python() const {
  py::dict out;
  py::list geometry;
  for (const std::string& w : wkb_) geometry.append(py::bytes(w));
  out["geometry"] = geometry;
  py::list names;
  for (std::size_t f = 0; f < schema_.size(); ++f) {
    py::list column;
    for (const FieldValue& v : values_[f]) {
      if (std::holds_alternative<std::monostate>(v)) column.append(py::none());
      else if (const auto* i = std::get_if<std::int64_t>(&v)) column.append(py::int_(*i));
      else if (const auto* d = std::get_if<double>(&v)) column.append(py::float_(*d));
      else column.append(py::str(std::get<std::string>(v)));
    }
    out[py::str(schema_[f].name)] = column;
    names.append(py::str(schema_[f].name));
  }
  out["fields"] = names;
  return out;
}

}  // namespace geovor::python
