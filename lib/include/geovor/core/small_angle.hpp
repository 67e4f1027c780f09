/// \file small_angle.hpp
/// \brief atan, sin and cos of small angles by their Taylor polynomials: no libm call, so loops
/// over them vectorize, and a few times cheaper than std::atan2 / std::sin / std::cos.
///
/// Valid for |argument| <= kSmallAngleMax = 0.07 (4 degrees): there the first omitted term is
/// below 1e-20 of the result, so the error is that of Horner's roundings, about one ulp.
#pragma once

namespace geovor {

/// The largest |t| (atan_small) or |u| (sin_small, cos_small, radians) these are valid for.
inline constexpr double kSmallAngleMax = 0.07;

/// atan(t) for |t| <= kSmallAngleMax (terms to t^15).
inline double atan_small(double t) {
  const double t2 = t * t;
  return t * (1 + t2 * (-1.0 / 3 + t2 * (1.0 / 5 + t2 * (-1.0 / 7 + t2 * (1.0 / 9 + t2 * (-1.0 / 11 + t2 * (1.0 / 13 - t2 / 15)))))));
}

/// sin(u) for |u| <= kSmallAngleMax (terms to u^11).
inline double sin_small(double u) {
  const double u2 = u * u;
  return u * (1 + u2 * (-1.0 / 6 + u2 * (1.0 / 120 + u2 * (-1.0 / 5040 + u2 * (1.0 / 362880 - u2 / 39916800)))));
}

/// cos(u) for |u| <= kSmallAngleMax (terms to u^10).
inline double cos_small(double u) {
  const double u2 = u * u;
  return 1 + u2 * (-0.5 + u2 * (1.0 / 24 + u2 * (-1.0 / 720 + u2 * (1.0 / 40320 - u2 / 3628800))));
}

}  // namespace geovor
