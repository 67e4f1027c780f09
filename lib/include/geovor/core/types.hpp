/// \file types.hpp
/// \brief Vocabulary types of geovor: unit vectors and flat-array indices.
#pragma once

#include <cstdint>
#include <limits>

namespace geovor {

/// Index of a site, a triangle or a half-edge in the flat arrays of a triangulation.
using SiteId = std::uint32_t;
using TriId = std::uint32_t;
using HalfedgeId = std::uint32_t;

/// Sentinel for "no such index" (geogram's NO_INDEX).
inline constexpr std::uint32_t kNoIndex = std::numeric_limits<std::uint32_t>::max();

/// A point of R^3; for sites, a unit vector (the direction of the site from the Earth's centre).
struct Vec3 {
  double x = 0, y = 0, z = 0;
  friend constexpr bool operator==(const Vec3&, const Vec3&) = default;
};

constexpr Vec3 operator-(const Vec3& a, const Vec3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
constexpr Vec3 operator+(const Vec3& a, const Vec3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
constexpr Vec3 operator*(double s, const Vec3& a) { return {s * a.x, s * a.y, s * a.z}; }
constexpr double dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
constexpr double norm2(const Vec3& a) { return dot(a, a); }

/// The type of a field of a layer, named as OGR names them: Integer (32 bits), Integer64, Real
/// (double), Date (YYYY-MM-DD), DateTime (ISO 8601), String (UTF-8 text).
enum class FieldType { Integer, Integer64, Real, Date, DateTime, String };

/// The OGR name of a type ("Integer", "Integer64", "Real", "Date", "DateTime", "String").
constexpr const char* to_string(FieldType t) {
  switch (t) {
    case FieldType::Integer:
      return "Integer";
    case FieldType::Integer64:
      return "Integer64";
    case FieldType::Real:
      return "Real";
    case FieldType::Date:
      return "Date";
    case FieldType::DateTime:
      return "DateTime";
    case FieldType::String:
      return "String";
  }
  return "?";
}

/// Sign of a predicate: -1, 0 or +1.
enum class Sign : int { Negative = -1, Zero = 0, Positive = 1 };

}  // namespace geovor
