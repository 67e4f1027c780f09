// HttpServer over real loopback sockets, with Boost.Beast's client: keep-alive, HEAD, a body over
// the limit refused before it is sent, Expect: 100-continue, a malformed target, a POST beside
// GETs, the connection limit, and stop() with idle connections open.
#define BOOST_BEAST_USE_STD_STRING_VIEW
#include "http_server.hpp"

#include <gtest/gtest.h>

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <thread>

#include "served_sites.hpp"

namespace geovor::service {
namespace {

namespace beast = boost::beast;
namespace http = beast::http;
namespace net = boost::asio;
using tcp = net::ip::tcp;
using Reply = http::response<http::string_body>;

std::shared_ptr<const ServedData> sites() { return served_sites(40); }

// A server on a free loopback port, answering on its own thread until the test ends.
struct Running {
  explicit Running(ServerOptions options = {}) : server(data, with_free_port(options)), thread([this] { server.run(); }) {}
  ~Running() {
    server.stop();
    thread.join();
  }
  static ServerOptions with_free_port(ServerOptions o) {
    o.port = 0;
    o.threads = 2;
    return o;
  }
  LiveData data{[] { return sites(); }};
  HttpServer server;
  std::thread thread;
};

struct Client {
  explicit Client(int port) : stream(io) { stream.connect(tcp::endpoint(net::ip::make_address("127.0.0.1"), port)); }
  Reply ask(http::verb verb, const std::string& target, const std::string& body = {}) {
    http::request<http::string_body> req(verb, target, 11);
    req.set(http::field::host, "127.0.0.1");
    if (verb == http::verb::post) req.set(http::field::content_type, "text/csv");
    req.body() = body;
    req.prepare_payload();
    http::write(stream, req);
    return read(verb == http::verb::head);
  }
  Reply read(bool head = false) {
    Reply res;
    if (head) {
      http::response_parser<http::string_body> p;
      p.skip(true);
      http::read(stream, buffer, p);
      return p.release();
    }
    http::read(stream, buffer, res);
    return res;
  }
  net::io_context io;
  beast::tcp_stream stream;
  beast::flat_buffer buffer;
};

TEST(HttpServer, KeepsConnectionsAliveAndAnswersHead) {
  Running r;
  Client c(r.server.port());
  const Reply a = c.ask(http::verb::get, "/nearest?lat=10&lon=20&k=2");
  EXPECT_EQ(a.result_int(), 200);
  EXPECT_EQ(a.body(), r.data.current()->nearest.nearest({{"lat", "10"}, {"lon", "20"}, {"k", "2"}}).body);
  EXPECT_TRUE(a.keep_alive());
  const Reply h = c.ask(http::verb::head, "/nearest?lat=10&lon=20&k=2");  // the same connection
  EXPECT_EQ(h.result_int(), 200);
  EXPECT_EQ(h[http::field::content_length], std::to_string(a.body().size()));
  EXPECT_TRUE(h.body().empty());
  const Reply p = c.ask(http::verb::post, "/nearest?k=1", "lat,lon\n1,2\n3,4\n");
  EXPECT_EQ(p.body(), r.data.current()->nearest.join({{"k", "1"}}, "lat,lon\n1,2\n3,4\n", "text/csv").body);
  EXPECT_EQ(c.ask(http::verb::get, "/healthz").body(), "{\"status\":\"ok\",\"sites\":40}");
}

TEST(HttpServer, DecodesTheTargetOrRefusesIt) {
  Running r;
  Client c(r.server.port());
  const Reply ok = c.ask(http::verb::get, "/nearest?lat=%2D10.5&lon=20");
  EXPECT_EQ(ok.body(), r.data.current()->nearest.nearest({{"lat", "-10.5"}, {"lon", "20"}}).body);
  const Reply bad = c.ask(http::verb::get, "/nearest?lat=%zz");
  EXPECT_EQ(bad.result_int(), 400);
  EXPECT_NE(bad.body().find("not a request target"), std::string::npos) << bad.body();
  const Reply none = c.ask(http::verb::delete_, "/nearest");
  EXPECT_EQ(none.result_int(), 405);
  EXPECT_EQ(none[http::field::allow], "GET, HEAD, POST");
}

TEST(HttpServer, RefusesALargeBodyBeforeItIsSent) {
  ServerOptions o;
  o.max_body_bytes = 1000;
  Running r(o);
  Client c(r.server.port());
  http::request<http::empty_body> req(http::verb::post, "/nearest", 11);
  req.set(http::field::host, "127.0.0.1");
  req.content_length(5000);  // the body is never sent
  http::write(c.stream, req);
  const Reply res = c.read();
  EXPECT_EQ(res.result_int(), 413);
  EXPECT_NE(res.body().find("1000 bytes"), std::string::npos) << res.body();
  EXPECT_FALSE(res.keep_alive());
}

TEST(HttpServer, ALargeBodySentWholeStillGetsItsAnswer) {
  ServerOptions o;
  o.max_body_bytes = 1000;
  Running r(o);
  Client c(r.server.port());
  // urllib and most clients send the whole body before reading: the server must not reset the
  // connection under them after its early 413.
  const Reply res = c.ask(http::verb::post, "/nearest", std::string(std::size_t{4} << 20, 'x'));
  EXPECT_EQ(res.result_int(), 413);
  EXPECT_FALSE(res.keep_alive());
}

TEST(HttpServer, AnswersExpectContinue) {
  Running r;
  Client c(r.server.port());
  http::request<http::string_body> req(http::verb::post, "/nearest", 11);
  req.set(http::field::host, "127.0.0.1");
  req.set(http::field::content_type, "text/csv");
  req.set(http::field::expect, "100-continue");
  req.body() = "lat,lon\n5,6\n";
  req.prepare_payload();
  http::request_serializer<http::string_body> sr(req);
  http::write_header(c.stream, sr);
  http::response<http::empty_body> cont;
  http::read(c.stream, c.buffer, cont);
  EXPECT_EQ(cont.result(), http::status::continue_);
  http::write(c.stream, sr);
  const Reply res = c.read();
  EXPECT_EQ(res.result_int(), 200);
  EXPECT_EQ(res.body(), r.data.current()->nearest.join({}, "lat,lon\n5,6\n", "text/csv").body);
}

TEST(HttpServer, AcceptsPastTheConnectionLimitOnceOneCloses) {
  ServerOptions o;
  o.connections = 1;
  Running r(o);
  auto first = std::make_unique<Client>(r.server.port());
  EXPECT_EQ(first->ask(http::verb::get, "/healthz").result_int(), 200);
  Client second(r.server.port());  // in the backlog until the first closes
  http::request<http::empty_body> req(http::verb::get, "/healthz", 11);
  req.set(http::field::host, "127.0.0.1");
  http::write(second.stream, req);
  first.reset();
  EXPECT_EQ(second.read().result_int(), 200);
}

TEST(HttpServer, StopClosesIdleConnectionsAndReturns) {
  auto r = std::make_unique<Running>();
  Client idle(r->server.port());
  EXPECT_EQ(idle.ask(http::verb::get, "/healthz").result_int(), 200);
  r.reset();  // stop() and join: would wait for the keep-alive timeout if idle connections held it
  Reply res;
  beast::error_code ec;
  http::read(idle.stream, idle.buffer, res, ec);
  EXPECT_TRUE(ec);  // closed by the server
}

}  // namespace
}  // namespace geovor::service
