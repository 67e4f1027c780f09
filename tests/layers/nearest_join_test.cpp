// The nearest-site join against brute force (every site's great-circle or geodesic distance),
// its malformed-line reports against the lines written into the input, and its output against
// itself over threads and block sizes.
#include "geovor/layers/nearest_join.hpp"

#include <GeographicLib/Geodesic.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "geovor/core/error.hpp"
#include "geovor/geo/lat_lon.hpp"
#include "geovor/geo/site_encoder.hpp"
#include "geovor/geo/site_reader.hpp"

namespace geovor {
namespace {

struct Site {
  std::string id_csv;  // as written in the output (quoted when needed)
  double lat, lon;
};

// Random sites; site 3's id holds a comma and a quote, so it is written quoted.
std::vector<Site> make_sites(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1), lon(-180, 180);
  std::vector<Site> sites;
  for (std::size_t i = 0; i < n; ++i) {
    char id[32], lat_text[32], lon_text[32];
    std::snprintf(id, sizeof id, "S%zu", i);
    std::snprintf(lat_text, sizeof lat_text, "%.6f", std::asin(u(rng)) * 180 / M_PI);
    std::snprintf(lon_text, sizeof lon_text, "%.6f", lon(rng));
    sites.push_back({id, std::stod(lat_text), std::stod(lon_text)});
  }
  sites[3].id_csv = "\"a,b \"\"c\"\"\"";  // the id a,b "c"
  return sites;
}

SiteIndex make_index(const std::vector<Site>& sites) {
  std::ostringstream csv;
  csv.precision(17);
  csv << "id,lat,lon\n";
  for (const Site& s : sites) csv << s.id_csv << ',' << s.lat << ',' << s.lon << '\n';
  std::istringstream in(csv.str());
  return build_site_index(read_sites_csv(in, "sites.csv"));
}

struct Result {
  std::string csv;
  std::vector<MalformedQuery> malformed;
  NearestJoinReport report;
};

Result join(const SiteIndex& index, const std::string& queries, const NearestJoinOptions& options) {
  std::FILE* f = fmemopen(const_cast<char*>(queries.data()), queries.size(), "rb");
  if (queries.empty()) f = std::fopen("/dev/null", "rb");
  EXPECT_NE(f, nullptr);
  Result r;
  r.report = nearest_join(
      index, f, "queries.csv", options, [&](std::string_view s) { r.csv += s; },
      [&](const MalformedQuery& m) { r.malformed.push_back(m); });
  std::fclose(f);
  return r;
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string cur;
  for (const char c : s) {
    if (c == sep) {
      out.push_back(cur);
      cur.clear();
    } else {
      cur.push_back(c);
    }
  }
  if (!cur.empty()) out.push_back(cur);
  return out;
}

// Brute force: every site's distance from the query, nearest first.
std::vector<std::pair<double, std::size_t>> brute(const std::vector<Site>& sites, double lat, double lon, Metric m) {
  std::vector<std::pair<double, std::size_t>> v;
  const Vec3 q = SiteEncoder::from_lat_lon(lat, lon);
  for (std::size_t i = 0; i < sites.size(); ++i) {
    double d = 0;
    if (m == Metric::Geodesic) {
      GeographicLib::Geodesic::WGS84().Inverse(lat, lon, sites[i].lat, sites[i].lon, d);
    } else {
      const Vec3 p = SiteEncoder::from_lat_lon(sites[i].lat, sites[i].lon);
      const double dx = q.x - p.x, dy = q.y - p.y, dz = q.z - p.z;
      d = 2 * SiteEncoder::kEarthRadiusM * std::asin(std::sqrt(dx * dx + dy * dy + dz * dz) / 2);
    }
    v.emplace_back(d, i);
  }
  std::sort(v.begin(), v.end());
  return v;
}

struct Query {
  double lat, lon;
};

std::vector<Query> random_queries(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1), lon(-180, 180);
  std::vector<Query> q;
  for (std::size_t i = 0; i < n; ++i) q.push_back({std::asin(u(rng)) * 180 / M_PI, lon(rng)});
  return q;
}

// Every output row against brute force: query_id, rank, site_index, site_id, distance_m.
void check_rows(const std::vector<Site>& sites, const std::vector<Query>& queries, const std::vector<std::string>& ids,
                const std::string& csv, std::size_t k, bool rank, Metric m) {
  const std::vector<std::string> lines = split(csv, '\n');
  ASSERT_EQ(lines.size(), 1 + queries.size() * k);
  EXPECT_EQ(lines[0], rank ? "query_id,rank,site_index,site_id,distance_m" : "query_id,site_index,site_id,distance_m");
  for (std::size_t i = 0; i < queries.size(); ++i) {
    const auto truth = brute(sites, queries[i].lat, queries[i].lon, m);
    for (std::size_t r = 0; r < k; ++r) {
      const std::string& line = lines[1 + i * k + r];
      // The id of site 3 holds a comma: take the fields from both ends.
      const std::size_t a = line.find(','), z = line.rfind(',');
      ASSERT_NE(a, z) << line;
      EXPECT_EQ(line.substr(0, a), ids[i]);
      std::string rest = line.substr(a + 1, z - a - 1);
      if (rank) {
        EXPECT_EQ(rest.substr(0, rest.find(',')), std::to_string(r + 1));
        rest = rest.substr(rest.find(',') + 1);
      }
      const std::size_t site = std::stoul(rest.substr(0, rest.find(',')));
      EXPECT_EQ(site, truth[r].second) << line;
      EXPECT_EQ(rest.substr(rest.find(',') + 1), sites[truth[r].second].id_csv) << line;
      EXPECT_NEAR(std::stod(line.substr(z + 1)), truth[r].first, 1e-6) << line;
    }
  }
}

std::string format_queries(const std::vector<Query>& queries, bool header, bool ids) {
  std::ostringstream s;
  s.precision(17);
  if (header) s << (ids ? "lat,lon,id\n" : "lat,lon\n");
  for (std::size_t i = 0; i < queries.size(); ++i) {
    s << queries[i].lat << ',' << queries[i].lon;
    if (ids) s << ",q" << i;
    s << '\n';
  }
  return s.str();
}

TEST(NearestJoin, NearestSiteOfEveryQueryMatchesBruteForce) {
  const auto sites = make_sites(500, 1);
  const SiteIndex index = make_index(sites);
  const auto queries = random_queries(400, 2);
  for (const Metric m : {Metric::Sphere, Metric::Geodesic}) {
    NearestJoinOptions o;
    o.metric = m;
    // Without ids, query_id is the line number (the header is line 1).
    std::vector<std::string> ids;
    for (std::size_t i = 0; i < queries.size(); ++i) ids.push_back(std::to_string(i + 2));
    const Result r = join(index, format_queries(queries, true, false), o);
    check_rows(sites, queries, ids, r.csv, 1, false, m);
    EXPECT_EQ(r.report.answered, queries.size());
    EXPECT_EQ(r.report.malformed, 0u);
    EXPECT_FALSE(r.report.stopped);
  }
}

TEST(NearestJoin, KNearestWithRanksMatchesBruteForce) {
  const auto sites = make_sites(300, 3);
  const SiteIndex index = make_index(sites);
  const auto queries = random_queries(150, 4);
  std::vector<std::string> ids;
  for (std::size_t i = 0; i < queries.size(); ++i) ids.push_back("q" + std::to_string(i));
  for (const Metric m : {Metric::Sphere, Metric::Geodesic}) {
    NearestJoinOptions o;
    o.metric = m;
    o.k = 4;
    o.rank_column = true;
    o.threads = 2;
    check_rows(sites, queries, ids, join(index, format_queries(queries, true, true), o).csv, 4, true, m);
  }
}

// Threads and block sizes (down to blocks shorter than a line) change nothing in the output.
TEST(NearestJoin, OutputIndependentOfThreadsAndBlocks) {
  const auto sites = make_sites(2000, 5);
  const SiteIndex index = make_index(sites);
  std::string queries = format_queries(random_queries(5000, 6), false, true);
  queries += "1,2,x\nbad\n\n3,4,\"quoted, id\"\n";  // a malformed line, an empty one, a quoted id
  NearestJoinOptions one;
  const Result ref = join(index, queries, one);
  ASSERT_EQ(ref.malformed.size(), 1u);
  EXPECT_EQ(ref.malformed[0].line, 5002u);
  EXPECT_NE(ref.csv.find("\n\"quoted, id\","), std::string::npos);
  for (const unsigned threads : {1u, 2u, 3u, 7u, 50000u})
    for (const std::size_t block : {std::size_t{1}, std::size_t{100}, std::size_t{4096}, std::size_t{1} << 20}) {
      NearestJoinOptions o;
      o.threads = threads;
      o.block_bytes = block;
      const Result r = join(index, queries, o);
      EXPECT_EQ(r.csv, ref.csv) << threads << " threads, blocks of " << block;
      ASSERT_EQ(r.malformed.size(), 1u);
      EXPECT_EQ(r.malformed[0].line, 5002u);
      EXPECT_EQ(r.report.answered, 5002u);
    }
}

// Malformed lines are values with their line numbers; BOM, CRLF, empty lines and a last line
// without its end are read as such.
TEST(NearestJoin, MalformedLinesReportedInOrder) {
  const auto sites = make_sites(50, 7);
  const SiteIndex index = make_index(sites);
  const std::string queries =
      "\xEF\xBB\xBFid,lat,lon\r\n"  // line 1
      "a,10,20\r\n"                 // 2
      "b,abc,5\r\n"                 // 3
      "\r\n"                        // 4 (empty)
      "c,1\n"                       // 5
      "d,10,1000\n"                 // 6
      "e,-10,-20";                  // 7, no line end
  for (const unsigned threads : {1u, 3u}) {
    NearestJoinOptions o;
    o.threads = threads;
    o.block_bytes = 8;
    const Result r = join(index, queries, o);
    ASSERT_EQ(r.malformed.size(), 3u);
    EXPECT_EQ(r.malformed[0].line, 3u);
    EXPECT_EQ(r.malformed[0].reason, "lat: 'abc' is not a number");
    EXPECT_EQ(r.malformed[1].line, 5u);
    EXPECT_EQ(r.malformed[2].line, 6u);
    EXPECT_EQ(r.report.answered, 2u);
    EXPECT_EQ(r.report.malformed, 3u);
    const auto lines = split(r.csv, '\n');
    ASSERT_EQ(lines.size(), 3u);
    EXPECT_EQ(lines[1].substr(0, 2), "a,");
    EXPECT_EQ(lines[2].substr(0, 2), "e,");
  }
}

// strict: the answers before the first malformed line, nothing after it.
TEST(NearestJoin, StrictStopsAtTheFirstMalformedLine) {
  const auto sites = make_sites(50, 8);
  const SiteIndex index = make_index(sites);
  std::string queries = format_queries(random_queries(3000, 9), false, false);
  queries += "oops\n" + format_queries(random_queries(3000, 10), false, false) + "bad again\n";
  for (const unsigned threads : {1u, 2u, 4u}) {
    NearestJoinOptions o;
    o.threads = threads;
    o.strict = true;
    o.block_bytes = 1000;
    const Result r = join(index, queries, o);
    EXPECT_TRUE(r.report.stopped);
    EXPECT_EQ(r.report.answered, 3000u);
    ASSERT_EQ(r.malformed.size(), 1u);
    EXPECT_EQ(r.malformed[0].line, 3001u);
    EXPECT_EQ(split(r.csv, '\n').size(), 3001u);
  }
}

TEST(NearestJoin, EmptyStreamWritesTheHeader) {
  const SiteIndex index = make_index(make_sites(10, 11));
  const Result r = join(index, "", {});
  EXPECT_EQ(r.csv, "query_id,site_index,site_id,distance_m\n");
  EXPECT_EQ(r.report.answered, 0u);
  const Result bom = join(index, "\xEF\xBB\xBF", {});
  EXPECT_EQ(bom.csv, r.csv);
}

TEST(NearestJoin, HeaderWithoutCoordinatesIsBadData) {
  const SiteIndex index = make_index(make_sites(10, 12));
  try {
    join(index, "name,value\nx,1\n", {});
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::BadData);
  }
}

// A read error is an I/O error naming the stream; the rows before it stay written.
TEST(NearestJoin, ReadErrorIsIoError) {
  const SiteIndex index = make_index(make_sites(10, 13));
  std::FILE* dir = std::fopen("/", "rb");
  ASSERT_NE(dir, nullptr);
  try {
    nearest_join(index, dir, "a_directory", {}, [](std::string_view) {});
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::Io);
    EXPECT_NE(std::string(e.what()).find("a_directory: read error"), std::string::npos) << e.what();
  }
  std::fclose(dir);
}

}  // namespace
}  // namespace geovor
