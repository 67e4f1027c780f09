/// \file live_data.hpp
/// \brief What `geovor serve` answers from, and its reload: the data are loaded whole by a
/// function (the index and the layers, from their paths), then swapped in at once. A request
/// holds the data it started with (a shared_ptr) until it is answered, so no request in flight
/// fails or sees half of each; a load that fails leaves the old data serving.
#pragma once

#include <functional>
#include <memory>
#include <mutex>
#include <string>

#include "features_service.hpp"
#include "nearest_service.hpp"

namespace geovor::service {

/// The data served, loaded together and replaced together.
struct ServedData {
  NearestService nearest;
  FeaturesService features;  ///< "sites", and "cells" when a cells layer is served
};

/// The data served for `index` and, unless `cells_path` is empty, the layer of cells there
/// (read_json_features: GDAL), the collection "cells".
/// @exception Error from read_json_features, naming the file.
std::shared_ptr<const ServedData> make_served_data(SiteIndex index, const std::string& cells_path,
                                                   const ServiceOptions& options);

/// Loads the served data (from their paths); throws Error when it cannot.
using LoadServedData = std::function<std::shared_ptr<const ServedData>()>;

/// What a reload did.
struct ReloadResult {
  bool ok = false;
  std::string message;  ///< ok: what is served now; else why the load failed (the old data kept)
};

class LiveData {
 public:
  /// Loads the data now. @exception whatever `load` throws (nothing to serve).
  explicit LiveData(LoadServedData load);
  /// The data a request is answered from (kept alive by the pointer, whatever reloads do).
  std::shared_ptr<const ServedData> current() const;
  /// Loads the data anew and swaps them in; on failure the old data stay. One reload at a time
  /// (a second one waits); requests go on meanwhile.
  ReloadResult reload();

 private:
  LoadServedData load_;
  mutable std::mutex current_mutex_;  // guards current_ (a copy of the pointer, never the load)
  std::shared_ptr<const ServedData> current_;
  std::mutex reload_mutex_;
};

}  // namespace geovor::service
