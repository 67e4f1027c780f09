/// \file nearest_service.hpp
/// \brief The handlers of `geovor serve` (issue 34), independent of HTTP: each takes a request's
/// query parameters and returns the response's status, content type and body, so that the HTTP
/// server, the tests and a fuzz target call the same code. They answer with the library's own
/// API (Locator, k_nearest: locate/), exactly as `geovor nearest` does.
#pragma once

#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <string_view>

#include "geovor/layers/nearest_join.hpp"
#include "geovor/locate/index_file.hpp"

namespace geovor::service {

/// A response: HTTP status, media type and body.
struct Response {
  int status = 200;
  std::string content_type = "application/geo+json";
  std::string body;
};

/// A request's query parameters (name -> value, repeated names kept in order).
using Params = std::multimap<std::string, std::string>;

/// Options of NearestService; every default is documented.
struct ServiceOptions {
  /// The largest k a request may ask. DEFAULT: 100.
  std::size_t max_k = 100;
  /// Threads of one POST /nearest join (NearestJoinOptions::threads); 0 means one per core.
  /// DEFAULT: 0.
  unsigned join_threads = 0;
};

class NearestService {
 public:
  /// The service of `index` (moved in; answers are read-only, so one service serves every thread).
  explicit NearestService(SiteIndex index, ServiceOptions options = {});

  /// GET /nearest?lat=..&lon=..[&k=..][&metric=sphere|geodesic|power][&max_distance_m=..][&fields=a,b]:
  /// a GeoJSON FeatureCollection of the k nearest sites, nearest first (ties to the lower site
  /// index), each a Point at its first row's position with site_index, site_id, rank, distance_m
  /// (metres, shortest round-trip decimal) and the site's columns (all of them, or those named by
  /// fields, as read). metric defaults to the index's (power for weighted sites, else sphere).
  /// A bad request is 400 with {"error": "...", "parameter": NAME} naming the parameter and why
  /// (missing, not a number, latitude outside [-90, 90], k outside 1..max_k, unknown metric or
  /// field, a metric the sites do not take, a repeated or unknown parameter).
  Response nearest(const Params& params) const;
  /// POST /nearest[?k=..][&metric=..][&max_distance_m=..][&fields=a,b][&lat_field=..][&lon_field=..][&id_field=..]
  /// with a CSV body (Content-Type text/csv, text/plain, application/csv, application/octet-stream
  /// or none): the spatial join of `geovor nearest` (layers/nearest_join.hpp), in the body's order,
  /// as the same CSV bytes as `geovor nearest --queries BODY` with the same options. A GeoJSON
  /// FeatureCollection of points (application/geo+json) or text sequence (application/geo+json-seq,
  /// application/x-ndjson: RS-separated or one feature per line) is read through GDAL
  /// (read_sites_ogr_bytes: needs the library with GDAL) and answered in its own framing and media
  /// type, the bytes of `geovor nearest -o OUT.geojson` (or .geojsonl, .geojsons); a feature that
  /// is no point is a 400 naming it. (fields names
  /// the site columns joined, --site-fields; lat_field, lon_field, id_field name the body's
  /// columns, --query-lat-field ...; k adds the rank column, as --k does). The body is read whole
  /// (HttpServer limits its size); the answer is built whole, so that a malformed body is refused:
  /// 400 naming its first malformed line and listing up to 100 of them ({"error", "line",
  /// "malformed": [{"line", "reason"}]}), with nothing answered. Another media type is 415
  /// (parameter "Content-Type"); an empty body, a header without coordinates or a column named
  /// but absent is 400.
  Response join(const Params& params, std::string_view body, std::string_view content_type) const;
  /// GET /healthz: 200 {"status":"ok","sites":N}.
  Response health() const;
  const SiteIndex& index() const { return index_; }

 private:
  // POST /nearest of GeoJSON points: read through GDAL (read_sites_ogr_bytes), answered as
  // geovor nearest writes GeoJSON or GeoJSONSeq.
  Response join_points(std::string_view body, bool collection, const std::string& type,
                       const NearestJoinOptions& options) const;
  SiteIndex index_;
  ServiceOptions options_;
};

/// A 400 (or other status) response with {"error": why, "parameter": name} (no name: no member).
Response error_response(int status, const std::string& why, const std::optional<std::string>& parameter = {});

}  // namespace geovor::service
