#include "http_server.hpp"

#include <httplib.h>

#include "geovor/core/error.hpp"
#include "geovor/core/parallel.hpp"

namespace geovor::service {
namespace {

void answer(httplib::Response& res, const Response& r) {
  res.status = r.status;
  res.set_content(r.body, r.content_type.c_str());
}

}  // namespace

struct HttpServer::Impl {
  httplib::Server server;
};

HttpServer::HttpServer(const NearestService& service, const ServerOptions& options) : impl_(std::make_unique<Impl>()) {
  httplib::Server& s = impl_->server;
  const unsigned threads = thread_count(options.threads);
  s.new_task_queue = [threads] { return new httplib::ThreadPool(threads); };
  s.Get("/nearest", [&service](const httplib::Request& req, httplib::Response& res) {
    Params params(req.params.begin(), req.params.end());
    answer(res, service.nearest(params));
  });
  s.Get("/healthz", [&service](const httplib::Request&, httplib::Response& res) { answer(res, service.health()); });
  s.set_error_handler([](const httplib::Request& req, httplib::Response& res) {
    if (!res.body.empty()) return;  // a handler's own error body
    answer(res, error_response(res.status, res.status == 404 ? req.path + ": no such resource" : "request refused"));
  });
  port_ = options.port == 0 ? s.bind_to_any_port(options.host) : (s.bind_to_port(options.host, options.port) ? options.port : -1);
  if (port_ <= 0)
    throw Error(ErrorCode::Io, options.host + ":" + std::to_string(options.port) + ": cannot listen there (in use, or not an address of this machine)");
}

HttpServer::~HttpServer() = default;

void HttpServer::run() { impl_->server.listen_after_bind(); }

void HttpServer::stop() { impl_->server.stop(); }

}  // namespace geovor::service
