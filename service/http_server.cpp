#include "http_server.hpp"

#include <httplib.h>
#include <sys/socket.h>

#include <algorithm>
#include <chrono>

#include "geovor/core/error.hpp"
#include "geovor/io/json_text.hpp"
#include "map_page.hpp"

namespace geovor::service {
namespace {

void answer(httplib::Response& res, Response&& r) {
  res.status = r.status;
  res.set_content(std::move(r.body), r.content_type.c_str());
}

// Requests on one keep-alive connection before it is closed.
constexpr std::size_t kKeepAliveRequests = 100000;

// The routes counted apart in /metrics.
const std::vector<std::string> kRoutes = {"GET /nearest", "POST /nearest", "GET /healthz", "GET /metrics", "POST /admin/reload",
                                          "GET /", "GET /collections", "GET /map"};

// When this worker thread began reading the request it answers now (set before routing).
thread_local std::chrono::steady_clock::time_point request_start;

std::string prometheus_gauges(const ServedData& data) {
  return "# HELP geovor_sites Sites served.\n# TYPE geovor_sites gauge\ngeovor_sites " +
         std::to_string(data.nearest.index().hierarchy.base().num_sites()) + "\n";
}

// The base of the links of OGC API - Features: the address the client used.
std::string base_url(const httplib::Request& req) { return "http://" + req.get_header_value("Host"); }

// OGC API - Features (FeaturesService).
void add_feature_routes(httplib::Server& s, LiveData& data) {
  s.Get("/", [&data](const httplib::Request& req, httplib::Response& res) {
    answer(res, data.current()->features.landing(base_url(req)));
  });
  s.Get("/api", [&data](const httplib::Request& req, httplib::Response& res) {
    answer(res, data.current()->features.api(base_url(req)));
  });
  s.Get("/conformance", [&data](const httplib::Request&, httplib::Response& res) {
    answer(res, data.current()->features.conformance());
  });
  s.Get("/collections", [&data](const httplib::Request& req, httplib::Response& res) {
    answer(res, data.current()->features.collections(base_url(req)));
  });
  s.Get(R"(/collections/([^/]+))", [&data](const httplib::Request& req, httplib::Response& res) {
    answer(res, data.current()->features.collection(req.matches[1], base_url(req)));
  });
  s.Get(R"(/collections/([^/]+)/items)", [&data](const httplib::Request& req, httplib::Response& res) {
    const Params params(req.params.begin(), req.params.end());
    answer(res, data.current()->features.items(req.matches[1], params, base_url(req)));
  });
  s.Get(R"(/collections/([^/]+)/items/([^/]+))", [&data](const httplib::Request& req, httplib::Response& res) {
    answer(res, data.current()->features.item(req.matches[1], req.matches[2], base_url(req)));
  });
}

// /map, Leaflet (Debian's libjs-leaflet, served from where it is installed) and the countries.
void add_map_routes(httplib::Server& s) {
  s.Get("/map", [](const httplib::Request&, httplib::Response& res) { res.set_content(map_page().data(), map_page().size(), "text/html; charset=utf-8"); });
  s.Get("/static/countries.geojson", [](const httplib::Request&, httplib::Response& res) {
    res.set_content(countries_geojson().data(), countries_geojson().size(), "application/geo+json");
  });
  s.set_mount_point("/static/leaflet", kLeafletDir);
}

}  // namespace

struct HttpServer::Impl {
  explicit Impl(LiveData& d) : data(d), metrics(kRoutes) {}
  LiveData& data;
  RequestMetrics metrics;
  httplib::Server server;
  int listening = -1;  // the listening socket
};

HttpServer::HttpServer(LiveData& data, const ServerOptions& options) : impl_(std::make_unique<Impl>(data)) {
  Impl& impl = *impl_;
  httplib::Server& s = impl.server;
  const std::size_t connections = std::max(1u, options.connections);
  s.new_task_queue = [connections] { return new httplib::ThreadPool(connections); };
  s.set_payload_max_length(options.max_body_bytes);
  s.set_read_timeout(options.read_timeout_s, 0);
  s.set_write_timeout(options.write_timeout_s, 0);
  s.set_keep_alive_timeout(options.keep_alive_timeout_s);
  s.set_tcp_nodelay(true);  // small responses go out at once, not after a delayed ACK (40 ms)
  s.set_keep_alive_max_count(kKeepAliveRequests);  // cpp-httplib closes after 5 by default: reconnections
  // The listening socket, to widen its backlog once bound (cpp-httplib's is 5: bursts of
  // connections waited for SYN retries, 1 s each). Replacing the default options drops its
  // SO_REUSEADDR, set here again (never SO_REUSEPORT: a port in use stays an error).
  s.set_socket_options([&impl](int sock) {
    const int yes = 1;
    ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    impl.listening = sock;
  });
  s.set_pre_routing_handler([](const httplib::Request&, httplib::Response&) {
    request_start = std::chrono::steady_clock::now();
    return httplib::Server::HandlerResponse::Unhandled;
  });
  s.set_logger([&impl](const httplib::Request& req, const httplib::Response& res) {
    const std::chrono::duration<double> took = std::chrono::steady_clock::now() - request_start;
    impl.metrics.record(req.method + " " + req.path, res.status, took.count());
  });

  s.Get("/nearest", [&impl](const httplib::Request& req, httplib::Response& res) {
    const Params params(req.params.begin(), req.params.end());
    answer(res, impl.data.current()->nearest.nearest(params));
  });
  s.Post("/nearest", [&impl](const httplib::Request& req, httplib::Response& res) {
    const Params params(req.params.begin(), req.params.end());
    answer(res, impl.data.current()->nearest.join(params, req.body, req.get_header_value("Content-Type")));
  });
  s.Get("/healthz", [&impl](const httplib::Request&, httplib::Response& res) {
    answer(res, impl.data.current()->nearest.health());
  });
  s.Get("/metrics", [&impl](const httplib::Request&, httplib::Response& res) {
    res.set_content(impl.metrics.text(prometheus_gauges(*impl.data.current())), "text/plain; version=0.0.4");
  });
  s.Post("/admin/reload", [this](const httplib::Request&, httplib::Response& res) {
    const ReloadResult r = reload();
    if (!r.ok) return answer(res, error_response(500, "reload failed, the previous data are still served: " + r.message));
    Response ok;
    ok.content_type = "application/json";
    ok.body = "{\"status\":\"reloaded\",\"served\":";
    append_json_string(ok.body, r.message);
    ok.body += "}";
    answer(res, std::move(ok));
  });
  add_feature_routes(s, impl.data);
  add_map_routes(s);
  s.set_error_handler([max = options.max_body_bytes](const httplib::Request& req, httplib::Response& res) {
    if (!res.body.empty()) return;  // a handler's own error body
    std::string why = "request refused";
    if (res.status == 404) why = req.path + ": no such resource";
    if (res.status == 405) why = req.method + " " + req.path + ": method not allowed";
    if (res.status == 413) why = "request body larger than " + std::to_string(max) + " bytes (ServerOptions::max_body_bytes)";
    answer(res, error_response(res.status, why));
  });
  port_ = options.port == 0 ? s.bind_to_any_port(options.host) : (s.bind_to_port(options.host, options.port) ? options.port : -1);
  if (port_ <= 0)
    throw Error(ErrorCode::Io, options.host + ":" + std::to_string(options.port) + ": cannot listen there (in use, or not an address of this machine)");
  ::listen(impl.listening, SOMAXCONN);  // a second listen() only sets the backlog
}

HttpServer::~HttpServer() = default;

void HttpServer::run() { impl_->server.listen_after_bind(); }

void HttpServer::stop() { impl_->server.stop(); }

ReloadResult HttpServer::reload() {
  ReloadResult r = impl_->data.reload();
  impl_->metrics.record_reload(r.ok);
  return r;
}

}  // namespace geovor::service
