/// \file http_server.hpp
/// \brief `geovor serve`'s HTTP layer: cpp-httplib (Debian's libcpp-httplib-dev) routes requests to
/// the handlers of the data served now (LiveData); no HTTP parsing of our own. Binds the host
/// given (127.0.0.1 by default).
///
/// Routes: GET /nearest, POST /nearest (NearestService), GET /healthz, GET /metrics (Prometheus
/// text: RequestMetrics), POST /admin/reload (LiveData::reload: 200 {"status":"reloaded",...},
/// or 500 {"error": why} with the old data still served). Anything else: 404 in JSON; a known
/// path with another method: 405. A body over ServerOptions::max_body_bytes: 413.
#pragma once

#include <cstddef>
#include <memory>
#include <string>

#include "live_data.hpp"
#include "request_metrics.hpp"

namespace geovor::service {

/// Options of HttpServer; every default is documented.
struct ServerOptions {
  /// Address to bind. DEFAULT: 127.0.0.1 (loopback only).
  std::string host = "127.0.0.1";
  /// Port; 0 picks a free one (port() says which). DEFAULT: 8080.
  int port = 8080;
  /// Connections served at once: cpp-httplib gives each its own thread of a pool for as long as it
  /// stays open (keep-alive included), so this is the pool's size; more connections wait to be
  /// accepted. Threads waiting on idle connections cost no CPU. DEFAULT: 256.
  unsigned connections = 256;
  /// The largest request body (POST /nearest's CSV), in bytes: a larger one is refused with 413
  /// before it is read. DEFAULT: 64 MiB (about 2.5 million lat,lon lines).
  std::size_t max_body_bytes = std::size_t{64} << 20;
  /// Seconds a connection may take to send a request (its body included), and to take the
  /// response, before it is closed. DEFAULT: 30.
  int read_timeout_s = 30;
  int write_timeout_s = 30;
  /// Seconds an idle keep-alive connection stays open. DEFAULT: 5.
  int keep_alive_timeout_s = 5;
};

class HttpServer {
 public:
  /// Binds the port. `data` must outlive the server.
  /// @exception Error(Io) naming the address when it cannot be bound.
  HttpServer(LiveData& data, const ServerOptions& options);
  ~HttpServer();
  /// The port bound.
  int port() const { return port_; }
  /// Answers requests until stop(); returns once the requests in flight are answered.
  void run();
  /// Stops run() (from another thread; not from a signal handler).
  void stop();
  /// Reloads the data (LiveData::reload), counted in /metrics; for SIGHUP and POST /admin/reload.
  ReloadResult reload();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  int port_ = 0;
};

}  // namespace geovor::service
