/// \file http_server.hpp
/// \brief `geovor serve`'s HTTP layer: Boost.Beast (HTTP/1.1, keep-alive) on Boost.Asio's event
/// loop, one thread per core: no HTTP parsing of our own (the target's percent-decoding:
/// request_target.hpp). Requests go to Router (router.hpp: the routes); a POST (a join, a reload) is answered on
/// a pool of its own so that it never holds up the quick GETs. Binds the host given (127.0.0.1 by
/// default). A body over ServerOptions::max_body_bytes: 413 before it is read; a target that is
/// no URL: 400.
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
  /// Threads of the event loop (and of the pool answering POSTs); 0 means one per core.
  /// DEFAULT: 0.
  unsigned threads = 0;
  /// Connections open at once (an idle keep-alive one costs a socket and a few KiB, no thread);
  /// more wait in the listen backlog until one closes (the process's open-file limit, often 1024, must
  /// allow them). DEFAULT: 1000.
  unsigned connections = 1000;
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
  std::shared_ptr<Impl> impl_;
  int port_ = 0;
};

}  // namespace geovor::service
