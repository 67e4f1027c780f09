// A FeatureWriter that keeps the features in memory for Python: each geometry as WKB (ISO,
// little-endian, longitude first), each field as a Python list; finish() does nothing.
#pragma once

#include <pybind11/pybind11.h>

#include <string>
#include <vector>

#include "geovor/io/feature_writer.hpp"

namespace geovor::python {

class MemoryFeatureWriter : public FeatureWriter {
 public:
  explicit MemoryFeatureWriter(std::vector<Field> schema) : schema_(std::move(schema)), values_(schema_.size()) {}
  void write(const Geometry& geometry, std::span<const FieldValue> values) override;
  void finish() override {}

  /// The features as a dict: "geometry" (a list of WKB bytes) and one list per field, in schema
  /// order ("fields": the names in that order). Needs the GIL.
  pybind11::dict to_python() const;

 private:
  std::vector<Field> schema_;
  std::vector<std::string> wkb_;
  std::vector<std::vector<FieldValue>> values_;  // by field, then feature
};

}  // namespace geovor::python
