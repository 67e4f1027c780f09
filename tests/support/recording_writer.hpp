/// \file recording_writer.hpp
/// \brief A FeatureWriter that keeps every feature in memory (no encoder, as the GDAL formats),
/// for tests that check what a layer writes.
#pragma once

#include <span>
#include <vector>

#include "geovor/io/feature_writer.hpp"

namespace geovor::testing {

class RecordingWriter : public FeatureWriter {
 public:
  struct Feature {
    Geometry geometry;
    std::vector<FieldValue> values;
  };
  void write(const Geometry& geometry, std::span<const FieldValue> values) override {
    features.push_back({geometry, std::vector<FieldValue>(values.begin(), values.end())});
  }
  void finish() override { finished = true; }

  std::vector<Feature> features;
  bool finished = false;
};

}  // namespace geovor::testing
