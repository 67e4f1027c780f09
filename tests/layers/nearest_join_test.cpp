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
#include "support/recording_writer.hpp"

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

// Every output row against brute force: query_id, rank, site_index, site_id, distance_m, then
// the query's line as written (`query_lines`, the stream's lines after its header).
void check_rows(const std::vector<Site>& sites, const std::vector<Query>& queries, const std::vector<std::string>& ids,
                const std::string& csv, std::size_t k, bool rank, Metric m, const std::string& query_text = "") {
  const std::vector<std::string> lines = split(csv, '\n');
  std::vector<std::string> query_lines = split(query_text, '\n');
  const std::string header = query_lines.empty() ? "" : "," + query_lines.front();
  ASSERT_EQ(lines.size(), 1 + queries.size() * k);
  EXPECT_EQ(lines[0], (rank ? "query_id,rank,site_index,site_id,distance_m" : "query_id,site_index,site_id,distance_m") + header);
  for (std::size_t i = 0; i < queries.size(); ++i) {
    const auto truth = brute(sites, queries[i].lat, queries[i].lon, m);
    for (std::size_t r = 0; r < k; ++r) {
      std::string line = lines[1 + i * k + r];
      if (!query_lines.empty()) {  // the query's fields, passed through as written
        const std::string tail = "," + query_lines[1 + i];
        ASSERT_GE(line.size(), tail.size());
        EXPECT_EQ(line.substr(line.size() - tail.size()), tail);
        line.resize(line.size() - tail.size());
      }
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
    const std::string text = format_queries(queries, true, false);
    const Result r = join(index, text, o);
    check_rows(sites, queries, ids, r.csv, 1, false, m, text);
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
    const std::string text = format_queries(queries, true, true);
    check_rows(sites, queries, ids, join(index, text, o).csv, 4, true, m, text);
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

// Enough sites that their ids are prepared on several threads (slices of 2^16 sites), quoted ids
// in every slice: the same output on any threads, each quoted id written as on one thread.
TEST(NearestJoin, QuotedSiteIdsOnAnyThreads) {
  auto sites = make_sites(140000, 8);
  for (std::size_t i = 5; i < sites.size(); i += 9973) sites[i].id_csv = "\"q" + std::to_string(i) + ", \"\"x\"\"\"";
  const SiteIndex index = make_index(sites);
  std::ostringstream queries;
  queries.precision(17);
  for (std::size_t i = 0; i < sites.size(); ++i)
    if (i % 997 == 0 || i % 9973 == 5) queries << sites[i].lat << ',' << sites[i].lon << '\n';
  NearestJoinOptions one;
  const Result ref = join(index, queries.str(), one);
  EXPECT_NE(ref.csv.find(",\"q9978, \"\"x\"\"\","), std::string::npos);
  EXPECT_NE(ref.csv.find(",\"q129654, \"\"x\"\"\","), std::string::npos);
  for (const unsigned threads : {2u, 3u, 0u}) {
    NearestJoinOptions o;
    o.threads = threads;
    o.block_bytes = 4096;
    EXPECT_EQ(join(index, queries.str(), o).csv, ref.csv) << threads << " threads";
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
    // Every query has a row: a malformed one an empty match, with its id and fields when it has
    // the header's three, else its line number and empty fields.
    const auto lines = split(r.csv, '\n');
    ASSERT_EQ(lines.size(), 6u);
    EXPECT_EQ(lines[0], "query_id,site_index,site_id,distance_m,id,lat,lon");
    EXPECT_EQ(lines[1].substr(0, 2), "a,");
    EXPECT_EQ(lines[1].substr(lines[1].size() - 8), ",a,10,20");
    EXPECT_EQ(lines[2], "b,,,,b,abc,5");
    EXPECT_EQ(lines[3], "5,,,,,,");
    EXPECT_EQ(lines[4], "d,,,,d,10,1000");
    EXPECT_EQ(lines[5].substr(0, 2), "e,");
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

// Named query columns (any name, such as a taxi feed's), every query column passed through, the
// join of a site field: the nearest site's own value, by brute force.
TEST(NearestJoin, NamedColumnsAndSiteFieldsMatchBruteForce) {
  const auto sites = make_sites(400, 14);
  std::ostringstream csv;
  csv.precision(17);
  csv << "id,lat,lon,label\n";
  for (std::size_t i = 0; i < sites.size(); ++i)
    csv << sites[i].id_csv << ',' << sites[i].lat << ',' << sites[i].lon << ",L" << i << '\n';
  std::istringstream in(csv.str());
  const SiteIndex index = build_site_index(read_sites_csv(in, "sites.csv"));
  const auto queries = random_queries(300, 15);
  std::ostringstream q;
  q.precision(17);
  q << "trip,pickup_longitude,pickup_latitude,lat\n";  // a `lat` column that is not the latitude
  for (std::size_t i = 0; i < queries.size(); ++i) q << "t" << i << ',' << queries[i].lon << ',' << queries[i].lat << ",x\n";
  NearestJoinOptions o;
  o.columns.lat_field = "pickup_latitude";
  o.columns.lon_field = "pickup_longitude";
  o.site_fields = {"LABEL"};
  const Result r = join(index, q.str(), o);
  const auto lines = split(r.csv, '\n');
  ASSERT_EQ(lines.size(), 1 + queries.size());
  EXPECT_EQ(lines[0], "query_id,site_index,site_id,distance_m,trip,pickup_longitude,pickup_latitude,lat,label");
  const auto qlines = split(q.str(), '\n');
  for (std::size_t i = 0; i < queries.size(); ++i) {
    const std::size_t nearest = brute(sites, queries[i].lat, queries[i].lon, Metric::Sphere)[0].second;
    const std::string& line = lines[1 + i];
    EXPECT_EQ(line.substr(0, line.find(',')), std::to_string(i + 2));  // no id column: the line number
    EXPECT_EQ(line.substr(line.find(',') + 1, line.find(',', line.find(',') + 1) - line.find(',') - 1), std::to_string(nearest));
    const std::string tail = "," + qlines[1 + i] + ",L" + std::to_string(nearest);
    EXPECT_EQ(line.substr(line.size() - tail.size()), tail) << line;
  }
}

TEST(NearestJoin, UnknownColumnsAreInvalidArguments) {
  const SiteIndex index = make_index(make_sites(10, 16));
  for (int which = 0; which < 2; ++which) {
    NearestJoinOptions o;
    if (which == 0) o.columns.lat_field = "pickup_latitude";
    if (which == 1) o.site_fields = {"elevation"};
    try {
      join(index, "lat,lon\n1,2\n", o);
      FAIL() << "no error";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::InvalidArgument);
      EXPECT_NE(std::string(e.what()).find(which == 0 ? "pickup_latitude" : "elevation"), std::string::npos) << e.what();
    }
  }
}

// max_distance_m: a query without a site within it gets one row with an empty match; with k, the
// rows are the sites within it (brute force), at least one per query.
TEST(NearestJoin, MaxDistanceGivesEmptyMatches) {
  const auto sites = make_sites(200, 17);
  const SiteIndex index = make_index(sites);
  const auto queries = random_queries(400, 18);
  const double d = 700e3;
  for (const std::size_t k : {std::size_t{1}, std::size_t{3}}) {
    NearestJoinOptions o;
    o.k = k;
    o.rank_column = k > 1;
    o.max_distance_m = d;
    o.threads = 2;
    const Result r = join(index, format_queries(queries, false, true), o);
    const auto lines = split(r.csv, '\n');
    std::size_t at = 1, unmatched = 0;
    for (std::size_t i = 0; i < queries.size(); ++i) {
      const auto truth = brute(sites, queries[i].lat, queries[i].lon, Metric::Sphere);
      std::size_t within = 0;
      while (within < k && truth[within].first <= d) ++within;
      if (within == 0) {
        ++unmatched;
        EXPECT_EQ(lines[at++], "q" + std::to_string(i) + (k > 1 ? ",,,," : ",,,"));
      }
      for (std::size_t w = 0; w < within; ++w, ++at) {
        const std::string prefix = "q" + std::to_string(i) + "," + (k > 1 ? std::to_string(w + 1) + "," : "") +
                                   std::to_string(truth[w].second) + ",";
        EXPECT_EQ(lines[at].substr(0, prefix.size()), prefix);
      }
    }
    EXPECT_EQ(at, lines.size());
    EXPECT_GT(unmatched, 10u);  // the test means something
    EXPECT_EQ(r.report.unmatched, unmatched);
    EXPECT_EQ(r.report.answered, queries.size());
  }
}

// A FeatureWriter the join owns, recording into a RecordingWriter the test keeps.
class ForwardingWriter : public FeatureWriter {
 public:
  explicit ForwardingWriter(testing::RecordingWriter& to) : to_(to) {}
  void write(const Geometry& g, std::span<const FieldValue> v) override { to_.write(g, v); }
  void finish() override { to_.finish(); }

 private:
  testing::RecordingWriter& to_;
};

// As features: the same matches as the CSV rows, a point at each query, field names renamed on a
// clash, and a malformed query as a null point with an empty match.
TEST(NearestJoin, FeaturesCarryTheCsvRowsAndNullPointsForMalformedQueries) {
  const auto sites = make_sites(300, 19);
  const SiteIndex index = make_index(sites);
  auto queries = random_queries(200, 20);
  std::string text = "site_id,lat,lon\n";
  for (Query& q : queries) {  // at the precision written, so that brute force sees the same points
    char v[40];
    std::snprintf(v, sizeof v, "%.9f", q.lat), q.lat = std::stod(v);
    std::snprintf(v, sizeof v, "%.9f", q.lon), q.lon = std::stod(v);
  }  // site_id clashes with the join's own field
  for (std::size_t i = 0; i < queries.size(); ++i) {
    char line[96];
    std::snprintf(line, sizeof line, "k%zu,%.9f,%.9f\n", i, queries[i].lat, queries[i].lon);
    text += line;
    if (i == 50) text += "bad,north,0\n";
  }
  NearestJoinOptions o;
  o.threads = 2;
  o.block_bytes = 512;
  testing::RecordingWriter rec;
  std::vector<Field> fields;
  std::FILE* f = fmemopen(text.data(), text.size(), "rb");
  const NearestJoinReport report = nearest_join(index, f, "q.csv", o, [&](const std::vector<Field>& fs) {
    fields = fs;
    return std::make_unique<ForwardingWriter>(rec);
  }, {});
  std::fclose(f);
  EXPECT_TRUE(rec.finished);
  EXPECT_EQ(report.answered, queries.size());
  EXPECT_EQ(report.malformed, 1u);
  std::vector<std::string> names;
  for (const Field& fl : fields) names.push_back(fl.name);
  EXPECT_EQ(names, (std::vector<std::string>{"query_id", "site_index", "site_id", "distance_m", "src_site_id", "lat", "lon"}));
  EXPECT_EQ(fields[1].type, FieldType::Integer64);
  EXPECT_EQ(fields[3].type, FieldType::Real);
  ASSERT_EQ(rec.features.size(), queries.size() + 1);
  for (std::size_t i = 0, q = 0; i < rec.features.size(); ++i) {
    const auto& ft = rec.features[i];
    if (i == 51) {
      EXPECT_TRUE(is_null_point(std::get<LonLat>(ft.geometry)));
      EXPECT_EQ(std::get<std::string>(ft.values[0]), "53");  // the line number: site_id is not an id column
      EXPECT_TRUE(std::holds_alternative<std::monostate>(ft.values[1]));
      EXPECT_EQ(std::get<std::string>(ft.values[4]), "bad");
      EXPECT_EQ(std::get<std::string>(ft.values[5]), "north");
      continue;
    }
    const auto truth = brute(sites, queries[q].lat, queries[q].lon, Metric::Sphere);
    const LonLat p = std::get<LonLat>(ft.geometry);
    EXPECT_NEAR(p.lat_deg, queries[q].lat, 1e-9);
    EXPECT_EQ(std::get<std::int64_t>(ft.values[1]), static_cast<std::int64_t>(truth[0].second));
    EXPECT_NEAR(std::get<double>(ft.values[3]), truth[0].first, 1e-6);
    EXPECT_EQ(std::get<std::string>(ft.values[4]), "k" + std::to_string(q));
    ++q;
  }
}

// A table of queries (an OGR layer's): its rows and rejected rows in row order, the same
// matches as the stream of the same queries.
TEST(NearestJoin, TableOfQueriesMatchesTheStream) {
  const auto sites = make_sites(300, 21);
  const SiteIndex index = make_index(sites);
  const auto queries = random_queries(100, 22);
  std::ostringstream csv;
  csv.precision(17);
  csv << "name,lat,lon\n";
  for (std::size_t i = 0; i < queries.size(); ++i) {
    csv << "n" << i << ',' << queries[i].lat << ',' << queries[i].lon << '\n';
    if (i == 10) csv << "bad,x,1\n";
  }
  std::istringstream in(csv.str());
  const SiteTable table = read_sites_csv(in, "q.csv");
  ASSERT_EQ(table.rejected.size(), 1u);
  NearestJoinOptions o;
  std::string from_table;
  std::vector<MalformedQuery> malformed;
  const NearestJoinReport report = nearest_join(
      index, table, o, [&](std::string_view t) { from_table += t; }, [&](const MalformedQuery& m) { malformed.push_back(m); });
  EXPECT_EQ(report.answered, queries.size());
  ASSERT_EQ(malformed.size(), 1u);
  EXPECT_EQ(malformed[0].row, 12u);
  const auto lines = split(from_table, '\n');
  ASSERT_EQ(lines.size(), queries.size() + 2);
  EXPECT_EQ(lines[0], "query_id,site_index,site_id,distance_m,name,lat,lon");
  EXPECT_EQ(lines[12], "12,,,,,,");
  const Result stream = join(index, csv.str(), o);
  const auto stream_lines = split(stream.csv, '\n');
  ASSERT_EQ(stream_lines.size(), lines.size());
  for (std::size_t i = 1; i < lines.size(); ++i) {
    if (i == 12) continue;
    // query_id (the id column `name`), site_index, site_id and distance_m as the stream's.
    const auto a = split(lines[i], ','), b = split(stream_lines[i], ',');
    for (std::size_t c = 0; c < 4; ++c) EXPECT_EQ(a[c], b[c]) << lines[i] << " | " << stream_lines[i];
  }
}

}  // namespace
}  // namespace geovor
