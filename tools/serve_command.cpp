// geovor serve INDEX: the nearest-site service over HTTP (service/: its handlers and the HTTP
// layer). Loads the index (or builds one from a site table), binds, answers until SIGTERM or
// SIGINT, then lets the requests in flight finish and exits 0.
#include <pthread.h>
#include <signal.h>

#include <cstdio>
#include <memory>
#include <string>
#include <thread>

#include "commands.hpp"
#include "geovor/locate/index_file.hpp"
#include "http_server.hpp"
#include "nearest_service.hpp"
#include "numeric_options.hpp"
#include "site_input.hpp"

namespace geovor::tools {
namespace {

struct ServeArgs {
  SiteInputArgs sites;
  service::ServerOptions server;
  int threads = 0;
};

int run(ServeArgs& args) {
  SiteIndex index = is_index_path(args.sites.input) ? load_index(args.sites.input, 2)
                                                      : build_index_from_table(args.sites, nullptr);
  const std::size_t sites = index.hierarchy.base().num_sites();
  const service::NearestService service(std::move(index));
  // SIGTERM and SIGINT are blocked here, so in every thread started below, and taken by sigwait.
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGTERM);
  sigaddset(&stop_signals, SIGINT);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);
  args.server.threads = static_cast<unsigned>(args.threads);
  service::HttpServer server(service, args.server);
  std::printf("geovor serve: http://%s:%d/ (%zu sites): GET /nearest?lat=..&lon=.., GET /healthz\n",
              args.server.host.c_str(), server.port(), sites);
  std::fflush(stdout);
  std::thread waiter([&] {
    int sig = 0;
    sigwait(&stop_signals, &sig);
    server.stop();
  });
  server.run();
  pthread_kill(waiter.native_handle(), SIGTERM);  // run() ended by itself: release the waiter
  waiter.join();
  return kOk;
}

}  // namespace

Command add_serve_command(CLI::App& app) {
  auto args = std::make_shared<ServeArgs>();
  CLI::App* cmd = app.add_subcommand("serve", "Answer nearest-site queries over HTTP (GET /nearest, GET /healthz)");
  add_site_input_options(cmd, args->sites);
  cmd->add_option("--host", args->server.host, "Address to listen on (default 127.0.0.1: this machine only)");
  cmd->add_option("--port", args->server.port, "Port (default 8080; 0: any free one, printed)")->check(integer_in(0, 65535));
  cmd->add_option("--threads", args->threads, "Threads answering requests (default 0: one per core)")
      ->check(integer_in(0, kMaxThreads));
  cmd->footer(
      "INPUT is an index file (geovor index) or a site table, indexed at start. Prints the address,\n"
      "then answers until SIGTERM or SIGINT (exit 0 once the requests in flight are answered).\n"
      "GET /nearest?lat=LAT&lon=LON[&k=K][&metric=sphere|geodesic|power][&max_distance_m=D][&fields=A,B]:\n"
      "a GeoJSON FeatureCollection of the K nearest sites (default 1, at most 100), nearest first,\n"
      "each a Point with site_index, site_id, rank, distance_m and the site's columns (or those\n"
      "named by fields), as exact as geovor nearest. A bad request is a 400 whose JSON body names\n"
      "the parameter and why. GET /healthz: {\"status\":\"ok\",\"sites\":N}.\n"
      "Example: geovor serve stations.gvi --port 8080 &  curl 'http://127.0.0.1:8080/nearest?lat=48.85&lon=2.35'");
  return {[args] { return run(*args); },
          [args] { return !is_index_path(args->sites.input) && site_input_needs_gdal(args->sites); }};
}

}  // namespace geovor::tools
