/// \file features_service.hpp
/// \brief `geovor serve`'s OGC API - Features (Part 1: Core, GeoJSON; OGC 17-069r4): the landing
/// page, /conformance, /collections, /collections/{id}, /collections/{id}/items and
/// /collections/{id}/items/{featureId}, over collections whose features' GeoJSON is made once,
/// when the data are loaded. Independent of HTTP, as NearestService. GDAL's OAPIF driver and QGIS
/// read them as layers.
///
/// Items: `limit` (1..10,000, default 10), `offset` (default 0; the "next" and "prev" links
/// carry it), `bbox=west,south,east,north` in degrees of WGS84 (CRS84; west > east crosses the
/// antimeridian) keeping the features whose bbox meets it, `f=json` (the only format). Every
/// response is JSON; a bad parameter is 400 naming it, an unknown collection or feature 404.
#pragma once

#include <array>
#include <string>
#include <unordered_map>
#include <vector>

#include "geovor/io/ogr_feature_json.hpp"
#include "geovor/locate/index_file.hpp"
#include "nearest_service.hpp"

namespace geovor::service {

/// One feature: its id, its bbox (west, south, east, north in degrees; west > east crosses the
/// antimeridian) and its GeoJSON Feature text with "id", "geometry" and "properties".
struct CollectionFeature {
  std::string id;
  std::array<double, 4> bbox{};
  std::string json;
};

/// A collection of features, as served.
struct Collection {
  std::string id, title, description;
  std::vector<CollectionFeature> features;
};

/// The sites of an index as a collection "sites": one Point per site at its first row's position,
/// id its site index, properties site_index, site_id and the site's columns (as read, as text).
Collection sites_collection(const SiteIndex& index);

/// A layer read by read_json_features (io/ogr_feature_json.hpp) as a collection: each feature's
/// id its FID.
Collection layer_collection(const JsonLayer& layer, std::string id, std::string title, std::string description);

class FeaturesService {
 public:
  explicit FeaturesService(std::vector<Collection> collections);
  /// Each takes the base URL of the links ("http://HOST:PORT", from the request's Host header).
  Response landing(const std::string& base) const;
  Response conformance() const;
  /// /api: the OpenAPI 3.0 definition of these paths (the landing page's "service-desc").
  Response api(const std::string& base) const;
  Response collections(const std::string& base) const;
  Response collection(const std::string& id, const std::string& base) const;
  Response items(const std::string& id, const Params& params, const std::string& base) const;
  Response item(const std::string& id, const std::string& feature_id, const std::string& base) const;
  const std::vector<Collection>& all() const { return collections_; }

 private:
  const Collection* find(const std::string& id) const;
  std::string collection_json(const Collection& c, const std::string& base) const;
  std::vector<Collection> collections_;
  std::vector<std::unordered_map<std::string, std::size_t>> by_id_;  // per collection: feature id -> index
};

}  // namespace geovor::service
