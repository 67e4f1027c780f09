/// \file http_server.hpp
/// \brief `geovor serve`'s HTTP layer: cpp-httplib (Debian's libcpp-httplib-dev) routes requests to
/// a NearestService; no HTTP parsing of our own. Binds the host given (127.0.0.1 by default).
#pragma once

#include <memory>
#include <string>

#include "nearest_service.hpp"

namespace geovor::service {

/// Options of HttpServer; every default is documented.
struct ServerOptions {
  /// Address to bind. DEFAULT: 127.0.0.1 (loopback only).
  std::string host = "127.0.0.1";
  /// Port; 0 picks a free one (port() says which). DEFAULT: 8080.
  int port = 8080;
  /// Worker threads answering requests; 0 means one per core. DEFAULT: 0.
  unsigned threads = 0;
};

class HttpServer {
 public:
  /// Binds the port (routes: GET /nearest, GET /healthz; anything else 404 in JSON).
  /// @exception Error(Io) naming the address when it cannot be bound.
  HttpServer(const NearestService& service, const ServerOptions& options);
  ~HttpServer();
  /// The port bound.
  int port() const { return port_; }
  /// Answers requests until stop(); returns once the requests in flight are answered.
  void run();
  /// Stops run() (from another thread; not from a signal handler).
  void stop();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  int port_ = 0;
};

}  // namespace geovor::service
