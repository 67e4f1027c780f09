#include "http_server.hpp"

#define BOOST_BEAST_USE_STD_STRING_VIEW  // Beast's views are std::string_view
#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <mutex>
#include <optional>
#include <thread>
#include <unordered_map>
#include <vector>

#include "geovor/core/error.hpp"
#include "request_target.hpp"
#include "router.hpp"

namespace geovor::service {

namespace beast = boost::beast;
namespace http = beast::http;
namespace net = boost::asio;
using tcp = net::ip::tcp;

namespace {

using Clock = std::chrono::steady_clock;

// Bytes of a body read at once: Beast reads no more than its buffer's spare capacity, which after
// a header is a few hundred bytes (26,000 reads for a 37 MB POST, 0.3 s, before this).
constexpr std::size_t kBodyReadBytes = std::size_t{1} << 16;

// The request as Router takes it; false when its target is no origin-form URL.
bool to_router_request(const http::request<http::string_body>& req, HttpRequest& out) {
  std::optional<RequestTarget> target = parse_request_target(req.target());
  if (!target) return false;
  out.method = std::string(req.method_string());
  out.path = std::move(target->path);
  out.params = std::move(target->query);
  out.host = std::string(req[http::field::host]);
  out.content_type = std::string(req[http::field::content_type]);
  out.body = req.body();
  return true;
}

}  // namespace

// One event loop per thread, each connection on one of them for its whole life: no strand, no
// lock and no wake-up across threads per request (those cost a third of the requests per second).
using Loop = net::io_context;
using Socket = net::basic_stream_socket<tcp, Loop::executor_type>;
using Stream = beast::basic_stream<tcp, Loop::executor_type>;

std::vector<std::unique_ptr<Loop>> make_loops(unsigned n) {
  std::vector<std::unique_ptr<Loop>> loops;
  for (unsigned i = 0; i < n; ++i) loops.push_back(std::make_unique<Loop>(1));  // concurrency hint: one thread
  return loops;
}

struct HttpServer::Impl : std::enable_shared_from_this<HttpServer::Impl> {
  Impl(LiveData& data, const ServerOptions& o)
      : options(o),
        threads(o.threads ? o.threads : std::max(1u, std::thread::hardware_concurrency())),
        metrics(Router::metric_routes()),
        router(data, metrics),
        loops(make_loops(threads)),
        slow_pool(threads),
        acceptor(*loops[0]),
        accept_wait(*loops[0]) {}

  class Session;
  void accept();
  void on_accept(beast::error_code ec, Socket socket);
  void stop_all();

  ServerOptions options;
  unsigned threads;
  RequestMetrics metrics;
  Router router;
  std::vector<std::unique_ptr<Loop>> loops;  // loops[0] also accepts
  std::vector<net::executor_work_guard<Loop::executor_type>> running;  // keeps idle loops running until stop
  std::size_t next_loop = 0;
  net::thread_pool slow_pool;  // POSTs: joins and reloads, off the event threads
  net::basic_socket_acceptor<tcp, Loop::executor_type> acceptor;
  net::steady_timer accept_wait;  // at ServerOptions::connections, accepting waits for a close
  std::atomic<bool> stopping{false};
  std::atomic<unsigned> open{0};
  std::mutex sessions_mutex;  // guards sessions
  std::unordered_map<const void*, std::weak_ptr<Session>> sessions;
};

// One connection: reads a request, answers it, and again while it is kept alive.
class HttpServer::Impl::Session : public std::enable_shared_from_this<Session> {
 public:
  Session(std::shared_ptr<Impl> server, Socket socket) : server_(std::move(server)), stream_(std::move(socket)) {}

  void start() {
    {
      std::lock_guard lock(server_->sessions_mutex);
      server_->sessions[this] = weak_from_this();
    }
    net::post(stream_.get_executor(), [self = shared_from_this()] { self->read_header(); });
  }

  ~Session() {
    std::lock_guard lock(server_->sessions_mutex);
    server_->sessions.erase(this);
    if (server_->open.fetch_sub(1) == server_->options.connections) {
      Impl* s = server_.get();  // a raw pointer: a handler left unrun at exit must not keep the server alive
      net::post(s->accept_wait.get_executor(), [s] { s->accept_wait.cancel(); });
    }
  }

  // From stop(): an idle connection (waiting for a request) closes now; one being answered closes
  // after its response.
  void close_if_idle() {
    net::dispatch(stream_.get_executor(), [self = shared_from_this()] {
      if (self->idle_) self->stream_.socket().close();
    });
  }

 private:
  void read_header() {
    if (server_->stopping) return stream_.socket().close();
    parser_.emplace();
    parser_->body_limit(server_->options.max_body_bytes);
    idle_ = buffer_.size() == 0;
    stream_.expires_after(std::chrono::seconds(first_ ? server_->options.read_timeout_s : server_->options.keep_alive_timeout_s));
    http::async_read_header(stream_, buffer_, *parser_, [self = shared_from_this()](beast::error_code ec, std::size_t) {
      self->on_header(ec);
    });
  }

  void on_header(beast::error_code ec) {
    idle_ = false;
    first_ = false;
    start_ = Clock::now();
    if (ec == http::error::body_limit) return refuse_body();
    if (ec) return stream_.socket().close();  // closed, timed out, or no HTTP: nothing to answer
    if (beast::iequals(parser_->get()[http::field::expect], "100-continue")) return send_continue();
    read_body();
  }

  void send_continue() {
    auto cont = std::make_shared<http::response<http::empty_body>>(http::status::continue_, parser_->get().version());
    stream_.expires_after(std::chrono::seconds(server_->options.write_timeout_s));
    http::async_write(stream_, *cont, [self = shared_from_this(), cont](beast::error_code ec, std::size_t) {
      if (ec) return self->stream_.socket().close();
      self->read_body();
    });
  }

  void read_body() {
    const auto length = parser_->content_length();
    if (!length || *length > buffer_.capacity()) buffer_.reserve(kBodyReadBytes);
    stream_.expires_after(std::chrono::seconds(server_->options.read_timeout_s));
    http::async_read(stream_, buffer_, *parser_, [self = shared_from_this()](beast::error_code ec, std::size_t) {
      if (ec == http::error::body_limit) return self->refuse_body();
      if (ec) return self->stream_.socket().close();
      self->handle();
    });
  }

  void refuse_body() {
    keep_alive_ = false;  // the body is not read: the connection cannot carry another request
    drain_ = true;
    Routed r;
    const std::string_view target = parser_->get().target();
    r.route = std::string(parser_->get().method_string()) + " " + std::string(target.substr(0, target.find('?')));
    r.response = error_response(413, "request body larger than " + std::to_string(server_->options.max_body_bytes) +
                                         " bytes (ServerOptions::max_body_bytes)");
    send(std::move(r));
  }

  void handle() {
    request_ = parser_->release();
    keep_alive_ = request_.keep_alive();
    HttpRequest req;
    if (!to_router_request(request_, req)) {
      Routed r;
      r.route = "other";
      r.response = error_response(400, std::string(request_.target()) + ": not a request target (an absolute path and a query)");
      return send(std::move(r));
    }
    if (!Router::is_slow(req)) return send(server_->router.route(req));
    // Off the event threads; the answer is written back on this connection's loop.
    net::post(server_->slow_pool, [self = shared_from_this(), req = std::move(req),
                                   guard = net::make_work_guard(stream_.get_executor())]() mutable {
      Routed r = self->server_->router.route(req);
      net::post(self->stream_.get_executor(), [self, r = std::move(r)]() mutable { self->send(std::move(r)); });
    });
  }

  void send(Routed r) {
    const bool head = request_.method() == http::verb::head;
    auto res = std::make_shared<http::response<http::string_body>>(static_cast<http::status>(r.response.status),
                                                                   request_.version() ? request_.version() : 11);
    res->set(http::field::content_type, r.response.content_type);
    if (!r.allow.empty()) res->set(http::field::allow, r.allow);
    res->keep_alive(keep_alive_ && !server_->stopping);
    res->content_length(r.response.body.size());
    if (!head) res->body() = std::move(r.response.body);
    const std::chrono::duration<double> took = Clock::now() - start_;
    server_->metrics.record(r.route, r.response.status, took.count());
    stream_.expires_after(std::chrono::seconds(server_->options.write_timeout_s));
    http::async_write(stream_, *res, [self = shared_from_this(), res](beast::error_code ec, std::size_t) {
      if (ec || !res->keep_alive()) {
        beast::error_code ignored;
        self->stream_.socket().shutdown(tcp::socket::shutdown_send, ignored);
        if (!ec && self->drain_) return self->drain();
        return self->stream_.socket().close();
      }
      self->request_ = {};
      if (self->buffer_.size() == 0 && self->buffer_.capacity() > kBodyReadBytes / 8) self->buffer_.shrink_to_fit();  // idle connections stay small
      self->read_header();
    });
  }

  // After a 413 sent before the body: read and drop what the client still sends (until it closes,
  // or read_timeout_s), so that closing does not reset the connection before it reads the 413.
  void drain() {
    idle_ = true;  // stop() closes it
    buffer_.clear();
    stream_.expires_after(std::chrono::seconds(server_->options.read_timeout_s));
    stream_.async_read_some(buffer_.prepare(kBodyReadBytes), [self = shared_from_this()](beast::error_code ec, std::size_t) {
      if (ec) return self->stream_.socket().close();
      self->drain();
    });
  }

  std::shared_ptr<Impl> server_;
  Stream stream_;
  beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
  http::request<http::string_body> request_;
  Clock::time_point start_;
  bool keep_alive_ = true;
  bool first_ = true;
  bool idle_ = false;
  bool drain_ = false;
};

void HttpServer::Impl::accept() {
  if (stopping) return;
  if (open.load() >= options.connections) {  // wait for a close (Session's destructor cancels the wait)
    accept_wait.expires_after(std::chrono::seconds(1));
    accept_wait.async_wait([self = shared_from_this()](beast::error_code) { self->accept(); });
    return;
  }
  Loop& loop = *loops[next_loop++ % loops.size()];  // round robin
  acceptor.async_accept(loop, beast::bind_front_handler(&Impl::on_accept, shared_from_this()));
}

void HttpServer::Impl::on_accept(beast::error_code ec, Socket socket) {
  if (ec == net::error::operation_aborted || stopping) return;
  if (ec) {  // out of file descriptors, say: try again shortly rather than spin
    accept_wait.expires_after(std::chrono::milliseconds(10));
    accept_wait.async_wait([self = shared_from_this()](beast::error_code) { self->accept(); });
    return;
  }
  socket.set_option(tcp::no_delay(true), ec);  // small responses go out at once, not after a delayed ACK
  ++open;
  std::make_shared<Session>(shared_from_this(), std::move(socket))->start();
  accept();
}

void HttpServer::Impl::stop_all() {
  stopping = true;
  net::post(acceptor.get_executor(), [this] {  // raw: stop() may come before run() or after it
    beast::error_code ignored;
    acceptor.close(ignored);
    accept_wait.cancel();
    for (auto& guard : running) guard.reset();  // each loop returns once its connections close
  });
  std::vector<std::shared_ptr<Session>> live;
  {
    std::lock_guard lock(sessions_mutex);
    for (auto& [key, weak] : sessions)
      if (auto s = weak.lock()) live.push_back(std::move(s));
  }
  for (auto& s : live) s->close_if_idle();
}

HttpServer::HttpServer(LiveData& data, const ServerOptions& options) : impl_(std::make_shared<Impl>(data, options)) {
  const std::string where = options.host + ":" + std::to_string(options.port);
  beast::error_code ec;
  const auto endpoints = tcp::resolver(*impl_->loops[0]).resolve(options.host, std::to_string(options.port), ec);
  if (ec || endpoints.empty()) throw Error(ErrorCode::Io, where + ": not an address of this machine (" + ec.message() + ")");
  const tcp::endpoint endpoint = *endpoints.begin();
  auto& a = impl_->acceptor;
  a.open(endpoint.protocol(), ec);
  if (!ec) a.set_option(net::socket_base::reuse_address(true), ec);  // never SO_REUSEPORT: a port in use stays an error
  if (!ec) a.bind(endpoint, ec);
  if (!ec) a.listen(net::socket_base::max_listen_connections, ec);
  if (ec) throw Error(ErrorCode::Io, where + ": cannot listen there (" + ec.message() + ")");
  port_ = a.local_endpoint().port();
}

HttpServer::~HttpServer() {
  stop();
  impl_->slow_pool.join();
}

void HttpServer::run() {
  Impl& impl = *impl_;
  for (auto& loop : impl.loops) impl.running.push_back(net::make_work_guard(*loop));
  net::post(*impl.loops[0], [&impl] {
    if (impl.stopping) return impl.running.clear();  // stop() came first
    impl.accept();
  });
  std::vector<std::thread> more;
  for (std::size_t i = 1; i < impl.loops.size(); ++i) more.emplace_back([&impl, i] { impl.loops[i]->run(); });
  impl.loops[0]->run();
  for (auto& t : more) t.join();
}

void HttpServer::stop() { impl_->stop_all(); }

ReloadResult HttpServer::reload() { return impl_->router.reload(); }

}  // namespace geovor::service
