#include "live_data.hpp"

#include <exception>
#include <utility>

namespace geovor::service {

std::shared_ptr<const ServedData> make_served_data(SiteIndex index, const std::string& cells_path,
                                                   const ServiceOptions& options) {
  std::vector<Collection> collections{sites_collection(index)};
  if (!cells_path.empty())
    collections.push_back(layer_collection(read_json_features(cells_path), "cells", "Cells",
                                           "The sites' cells (geovor cells), from " + cells_path));
  return std::make_shared<const ServedData>(
      ServedData{NearestService(std::move(index), options), FeaturesService(std::move(collections))});
}

LiveData::LiveData(LoadServedData load) : load_(std::move(load)), current_(load_()) {}

std::shared_ptr<const ServedData> LiveData::current() const {
  const std::lock_guard lock(current_mutex_);
  return current_;
}

ReloadResult LiveData::reload() {
  const std::lock_guard reloading(reload_mutex_);
  std::shared_ptr<const ServedData> fresh;
  try {
    fresh = load_();
  } catch (const std::exception& e) {
    return {false, e.what()};
  }
  const std::size_t sites = fresh->nearest.index().hierarchy.base().num_sites();
  std::shared_ptr<const ServedData> old;
  {
    const std::lock_guard lock(current_mutex_);
    old = std::exchange(current_, std::move(fresh));
  }
  // `old` is freed here, or by the last request still holding it.
  return {true, std::to_string(sites) + " sites"};
}

}  // namespace geovor::service
