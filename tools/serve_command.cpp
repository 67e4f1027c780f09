// geovor serve INDEX: the nearest-site service over HTTP (service/: its handlers, the reloadable
// data and the HTTP layer). Loads the index (or builds one from a site table), binds, answers
// until SIGTERM or SIGINT, then lets the requests in flight finish and exits 0; SIGHUP reloads.
#include <pthread.h>
#include <signal.h>

#include <cstdio>
#include <memory>
#include <string>
#include <thread>

#include "commands.hpp"
#include "geovor/locate/index_file.hpp"
#include "http_server.hpp"
#include "live_data.hpp"
#include "numeric_options.hpp"
#include "site_input.hpp"

namespace geovor::tools {
namespace {

struct ServeArgs {
  SiteInputArgs sites;
  service::ServerOptions server;
  service::ServiceOptions service;
  int threads = 0;
  std::size_t max_body_mb = 64;
  std::string cells;  // a layer of geovor cells served as the collection "cells"; "" for none
};

// Reads the data from their paths: at start, and again on each reload.
std::shared_ptr<const service::ServedData> load(ServeArgs& args) {
  SiteIndex index = is_index_path(args.sites.input) ? load_index(args.sites.input, args.sites.reader.threads)
                                                      : build_index_from_table(args.sites, nullptr);
  return service::make_served_data(std::move(index), args.cells, args.service);
}

// Waits for signals: SIGHUP reloads, SIGTERM or SIGINT stop the server.
void handle_signals(const sigset_t& signals, service::HttpServer& server) {
  for (;;) {
    int sig = 0;
    sigwait(&signals, &sig);
    if (sig != SIGHUP) break;
    const service::ReloadResult r = server.reload();
    std::fprintf(stderr, r.ok ? "geovor serve: reloaded: %s\n" : "geovor serve: reload failed, still serving the previous data: %s\n",
                 r.message.c_str());
  }
  server.stop();
}

int run(ServeArgs& args) {
  args.service.join_threads = static_cast<unsigned>(args.threads);
  args.server.threads = static_cast<unsigned>(args.threads);
  args.sites.reader.threads = static_cast<unsigned>(args.threads);  // reading the sites, or loading the index
  args.server.max_body_bytes = args.max_body_mb << 20;
  service::LiveData data([&args] { return load(args); });
  // These signals are blocked here, so in every thread started below, and taken by sigwait.
  sigset_t signals;
  sigemptyset(&signals);
  for (const int s : {SIGTERM, SIGINT, SIGHUP}) sigaddset(&signals, s);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  service::HttpServer server(data, args.server);
  std::printf("geovor serve: http://%s:%d/ (%zu sites): GET|POST /nearest, /collections, /map, /healthz, /metrics\n",
              args.server.host.c_str(), server.port(), data.current()->nearest.index().hierarchy.base().num_sites());
  std::fflush(stdout);
  std::thread waiter([&] { handle_signals(signals, server); });
  server.run();
  pthread_kill(waiter.native_handle(), SIGTERM);  // run() ended by itself: release the waiter
  waiter.join();
  return kOk;
}

}  // namespace

Command add_serve_command(CLI::App& app) {
  auto args = std::make_shared<ServeArgs>();
  CLI::App* cmd = app.add_subcommand("serve", "Answer nearest-site queries over HTTP (GET and POST /nearest)");
  add_site_input_options(cmd, args->sites);
  cmd->add_flag("-q,--quiet", args->sites.quiet, "No list of merged rows on stderr (rejected rows and reloads are still listed)");
  cmd->add_option("--cells", args->cells, "A layer of geovor cells (any OGR format), served as the collection 'cells'");
  cmd->add_option("--host", args->server.host, "Address to listen on (default 127.0.0.1: this machine only)");
  cmd->add_option("--port", args->server.port, "Port (default 8080; 0: any free one, printed)")->check(integer_in(0, 65535));
  add_threads_option(cmd, args->threads);
  cmd->add_option("--connections", args->server.connections, "Connections open at once; more wait to be accepted (default 1000)")
      ->check(integer_in(1, 1000000));
  cmd->add_option("--max-k", args->service.max_k, "The largest k a request may ask (default 100)")->check(integer_in(1, 10000));
  cmd->add_option("--max-body-mb", args->max_body_mb, "The largest POST body in MiB; larger: 413 (default 64)")
      ->check(integer_in(1, 4096));
  cmd->footer(
      "INPUT is an index file (geovor index) or a site table, indexed at start. Prints the address,\n"
      "then answers until SIGTERM or SIGINT (exit 0 once the requests in flight are answered).\n"
      "SIGHUP or POST /admin/reload reads INPUT again and swaps it in; if it fails, the old data stay.\n"
      "GET /nearest?lat=LAT&lon=LON[&k=K][&metric=sphere|geodesic|power][&max_distance_m=D][&fields=A,B]:\n"
      "a GeoJSON FeatureCollection of the K nearest sites (default 1, at most --max-k), nearest first,\n"
      "each a Point with site_index, site_id, rank, distance_m and the site's columns (or those\n"
      "named by fields), as exact as geovor nearest.\n"
      "POST /nearest[?k=..&fields=..&lat_field=..] with CSV (text/csv) or GeoJSON (application/geo+json,\n"
      "application/geo+json-seq) points: the join of geovor nearest, in the same bytes and format.\n"
      "OGC API - Features at / (collections sites and, with --cells, cells); a web map at /map.\n"
      "A bad request is a 400 whose JSON body names the parameter (or line) and why.\n"
      "GET /healthz: {\"status\":\"ok\",\"sites\":N}. GET /metrics: Prometheus text. Guide: docs/user-guide.md, Serving.\n"
      "Example: geovor serve stations.gvi --port 8080 &  curl 'http://127.0.0.1:8080/nearest?lat=48.85&lon=2.35'");
  return {[args] { return run(*args); },
          [] { return true; }};  // GeoJSON bodies and --cells are read through GDAL
}

}  // namespace geovor::tools
