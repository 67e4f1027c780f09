/// \file router.hpp
/// \brief `geovor serve`'s routes: a parsed request (method, decoded path and query, the headers
/// used) to the handler that answers it, independent of sockets, so that the HTTP layer, the
/// tests and the fuzz target route alike.
///
/// Routes: GET /nearest, POST /nearest (NearestService), GET /healthz, GET /metrics (Prometheus
/// text: RequestMetrics), POST /admin/reload (LiveData::reload: 200 {"status":"reloaded",...},
/// or 500 {"error": why} with the old data still served), OGC API - Features (/, /api,
/// /conformance, /collections[/{id}[/items[/{fid}]]]: FeaturesService), /map, its countries and
/// Leaflet (Debian's libjs-leaflet, read from where it is installed). HEAD is answered as GET.
/// Anything else: 404 in JSON; a known path with another method: 405 with Allow.
#pragma once

#include <string>
#include <string_view>

#include "live_data.hpp"
#include "nearest_service.hpp"
#include "request_metrics.hpp"

namespace geovor::service {

/// A request as the routes see it: the HTTP layer parses and percent-decodes it.
struct HttpRequest {
  std::string method;  ///< "GET", "POST", ...
  std::string path;    ///< decoded, without the query
  Params params;       ///< the decoded query
  std::string host;    ///< the Host header (the base of OGC API links)
  std::string content_type;
  std::string_view body;
};

/// A response and what the HTTP layer adds to it.
struct Routed {
  Response response;
  std::string route;  ///< the route counted in /metrics ("METHOD /path", or the path asked)
  std::string allow;  ///< a 405's Allow header, else empty
};

class Router {
 public:
  /// Routes of the data of `data` (which must outlive the router); `reload` is counted in `metrics`.
  Router(LiveData& data, RequestMetrics& metrics) : data_(data), metrics_(metrics) {}

  /// The routes counted apart in /metrics (RequestMetrics' constructor).
  static const std::vector<std::string>& metric_routes();

  /// True for the requests that may take long (a POST join, a reload): the HTTP layer answers
  /// them off its event threads.
  static bool is_slow(const HttpRequest& request);

  /// The answer to `request`.
  Routed route(const HttpRequest& request) const;

  /// Reloads the data (LiveData::reload), counted in /metrics; for SIGHUP and POST /admin/reload.
  ReloadResult reload() const;

 private:
  Response get(const HttpRequest& request, bool& found) const;
  Response post(const HttpRequest& request, bool& found) const;
  Response features(const HttpRequest& request, bool& found) const;
  LiveData& data_;
  RequestMetrics& metrics_;
};

}  // namespace geovor::service
