/// \file generators.cpp
/// \brief Deterministic point generators and the minimal lat/lon CSV loader of the test support.
#include "support/generators.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <random>

#include "geovor/core/error.hpp"

namespace geovor::testing {
namespace {

// 53 random bits -> [0, 1): exact and the same everywhere, unlike std::uniform_real_distribution.
double uniform01(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1p-53; }

double uniform_pm1(std::mt19937_64& rng) { return 2.0 * uniform01(rng) - 1.0; }

// Uniform in the unit ball, away from the centre so that normalising is well conditioned.
Vec3 in_unit_ball(std::mt19937_64& rng) {
  for (;;) {
    const Vec3 p{uniform_pm1(rng), uniform_pm1(rng), uniform_pm1(rng)};
    const double r2 = norm2(p);
    if (r2 <= 1.0 && r2 > 1e-6) return p;
  }
}

Vec3 from_lat_lon_deg(double lat_deg, double lon_deg) {
  const double lat = lat_deg * (std::numbers::pi / 180.0);
  const double lon = lon_deg * (std::numbers::pi / 180.0);
  return {std::cos(lat) * std::cos(lon), std::cos(lat) * std::sin(lon), std::sin(lat)};
}

// Reads one CSV record (quoted fields, "" escapes, line breaks inside quotes); false at end of file.
bool read_record(std::FILE* f, std::vector<std::string>& fields) {
  fields.assign(1, std::string());
  int c = std::getc(f);
  if (c == EOF) return false;
  bool quoted = false;
  for (; c != EOF; c = std::getc(f)) {
    if (quoted) {
      if (c == '"') {
        const int d = std::getc(f);
        if (d == '"') {
          fields.back() += '"';
        } else {
          quoted = false;
          if (d != EOF) std::ungetc(d, f);
        }
      } else {
        fields.back() += static_cast<char>(c);
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      fields.emplace_back();
    } else if (c == '\n') {
      break;
    } else if (c != '\r') {
      fields.back() += static_cast<char>(c);
    }
  }
  return true;
}

double parse_number(const std::string& s, const std::string& path, std::size_t line) {
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || end != s.c_str() + s.size() || !std::isfinite(v)) {
    throw Error(ErrorCode::BadData, path + ":" + std::to_string(line) + ": not a number: '" + s + "'");
  }
  return v;
}

std::vector<Vec3> load_from(std::FILE* f, const std::string& path) {
  std::vector<std::string> fields;
  if (!read_record(f, fields)) throw Error(ErrorCode::BadData, path + ": empty file");
  std::size_t lat_col = fields.size(), lon_col = fields.size();
  for (std::size_t i = 0; i < fields.size(); ++i) {
    if (fields[i] == "lat_deg") lat_col = i;
    if (fields[i] == "lon_deg") lon_col = i;
  }
  if (lat_col == fields.size() || lon_col == fields.size()) {
    throw Error(ErrorCode::BadData, path + ": header has no lat_deg and lon_deg columns");
  }
  std::vector<Vec3> points;
  std::size_t line = 1;
  while (read_record(f, fields)) {
    ++line;
    if (fields.size() == 1 && fields[0].empty()) continue;  // blank line
    if (fields.size() <= std::max(lat_col, lon_col)) {
      throw Error(ErrorCode::BadData, path + ":" + std::to_string(line) + ": too few fields");
    }
    const double lat = parse_number(fields[lat_col], path, line);
    const double lon = parse_number(fields[lon_col], path, line);
    points.push_back(normalized(from_lat_lon_deg(lat, lon)));
  }
  return points;
}

}  // namespace

Vec3 normalized(const Vec3& p) { return (1.0 / std::sqrt(norm2(p))) * p; }

std::vector<Vec3> uniform_on_sphere(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<Vec3> points;
  points.reserve(n);
  for (std::size_t i = 0; i < n; ++i) points.push_back(normalized(in_unit_ball(rng)));
  return points;
}

std::vector<Vec3> clustered(std::size_t n, std::size_t clusters, double spread_rad, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  if (clusters == 0) clusters = 1;
  std::vector<Vec3> centres;
  centres.reserve(clusters);
  for (std::size_t i = 0; i < clusters; ++i) centres.push_back(normalized(in_unit_ball(rng)));
  std::vector<Vec3> points;
  points.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3& c = centres[rng() % clusters];
    points.push_back(normalized(c + spread_rad * in_unit_ball(rng)));
  }
  return points;
}

std::vector<Vec3> on_great_circle(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<Vec3> points;
  points.reserve(n);
  while (points.size() < n) {
    // Rejection from the square: no libm, and z stays exactly 0 after normalising.
    const Vec3 p{uniform_pm1(rng), uniform_pm1(rng), 0.0};
    const double r2 = norm2(p);
    if (r2 <= 1.0 && r2 > 1e-6) points.push_back(normalized(p));
  }
  return points;
}

std::vector<Vec3> on_small_circle(std::size_t n, double lat_deg, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  const double lat = lat_deg * (std::numbers::pi / 180.0);
  const double c = std::cos(lat), z = std::sin(lat);
  std::vector<Vec3> points;
  points.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double lon = 2.0 * std::numbers::pi * uniform01(rng);
    points.push_back({c * std::cos(lon), c * std::sin(lon), z});
  }
  return points;
}

std::vector<Vec3> in_hemisphere(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<Vec3> points;
  points.reserve(n);
  while (points.size() < n) {
    const Vec3 p = normalized(in_unit_ball(rng));
    if (p.z > 0.1) points.push_back(p);
  }
  return points;
}

std::vector<Vec3> lat_lon_grid(double step_deg, double lat_min, double lat_max, double lon_min, double lon_max) {
  std::vector<Vec3> points;
  if (!(step_deg > 0) || lat_min > lat_max || lon_min > lon_max) return points;
  // Counts from integers, so rounding does not add or drop the last row.
  const auto count = [step_deg](double range) {
    return static_cast<std::size_t>(std::floor(range / step_deg + 1e-9)) + 1;
  };
  const std::size_t nlat = count(lat_max - lat_min);
  std::size_t nlon = count(lon_max - lon_min);
  const bool full_turn = lon_max - lon_min >= 360.0;
  if (full_turn && lon_min + static_cast<double>(nlon - 1) * step_deg >= lon_min + 360.0 - 1e-9) {
    --nlon;  // lon_min + 360 is the meridian lon_min again
  }
  for (std::size_t i = 0; i < nlat; ++i) {
    const double lat = lat_min + static_cast<double>(i) * step_deg;
    if (std::abs(std::abs(lat) - 90.0) < 1e-9) {
      points.push_back({0.0, 0.0, lat > 0 ? 1.0 : -1.0});
      continue;
    }
    for (std::size_t j = 0; j < nlon; ++j) {
      points.push_back(normalized(from_lat_lon_deg(lat, lon_min + static_cast<double>(j) * step_deg)));
    }
  }
  return points;
}

std::vector<Vec3> cube_corners() {
  std::vector<Vec3> points;
  for (int i = 0; i < 8; ++i) {
    points.push_back(normalized({(i & 1) ? 1.0 : -1.0, (i & 2) ? 1.0 : -1.0, (i & 4) ? 1.0 : -1.0}));
  }
  return points;
}

std::vector<Vec3> skinny_set(std::size_t n) {
  std::vector<Vec3> points;
  if (n == 0) n = 1;
  const double pi = std::numbers::pi;
  for (std::size_t k = 0; k <= n; ++k) {
    const double t = static_cast<double>(k) * pi / static_cast<double>(n);
    const double f = (t * t + 1.0) * pi / 2.0;
    points.push_back(normalized({std::cos(t) * std::sin(f), std::sin(t) * std::sin(f), std::cos(f)}));
  }
  points.push_back({1.0, 0.0, 0.0});
  points.push_back({0.0, 1.0, 0.0});
  points.push_back({0.0, 0.0, 1.0});
  points.push_back(normalized({-1.0, -1.0, -1.0}));
  return points;
}

std::vector<Vec3> poles_with_longitudes(std::size_t k) {
  std::vector<Vec3> points;
  for (std::size_t j = 0; j < k; ++j) points.push_back({0.0, 0.0, 1.0});
  for (std::size_t j = 0; j < k; ++j) points.push_back({0.0, 0.0, -1.0});
  for (const double lat : {89.9999, -89.9999}) {
    for (std::size_t j = 0; j < k; ++j) {
      const double lon = -180.0 + 360.0 * static_cast<double>(j) / static_cast<double>(k);
      points.push_back(normalized(from_lat_lon_deg(lat, lon)));
    }
  }
  return points;
}

std::vector<Vec3> load_lat_lon_csv_unit_vectors(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) throw Error(ErrorCode::Io, "cannot open " + path);
  try {
    std::vector<Vec3> points = load_from(f, path);
    std::fclose(f);
    return points;
  } catch (...) {
    std::fclose(f);
    throw;
  }
}

std::vector<Vec3> load_lat_lon_csv_gz_unit_vectors(const std::string& path) {
  std::FILE* probe = std::fopen(path.c_str(), "rb");
  if (probe == nullptr) throw Error(ErrorCode::Io, "cannot open " + path);
  std::fclose(probe);
  // Single quotes protect the path from the shell; an embedded quote is closed, escaped, reopened.
  std::string quoted = "'";
  for (const char ch : path) quoted += (ch == '\'') ? std::string("'\\''") : std::string(1, ch);
  quoted += "'";
  std::FILE* f = ::popen(("gzip -dc " + quoted).c_str(), "r");
  if (f == nullptr) throw Error(ErrorCode::Io, "cannot run gzip -dc on " + path);
  std::vector<Vec3> points;
  try {
    points = load_from(f, path);
  } catch (...) {
    ::pclose(f);
    throw;
  }
  if (::pclose(f) != 0) throw Error(ErrorCode::Io, "gzip -dc failed on " + path);
  return points;
}

}  // namespace geovor::testing
