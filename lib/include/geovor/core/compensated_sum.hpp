/// \file compensated_sum.hpp
/// \brief A running sum of doubles held as two non-overlapping terms (Shewchuk's two-sum): the
/// same arithmetic, bit for bit, as GeographicLib::Accumulator<double>, which PolygonArea uses,
/// but inline. GeographicLib's Math::sum is an out-of-line call into its shared library, one per
/// term, which showed in the cells' profile.
///
/// Error: the value is within about one ulp of the exact sum of the terms plus one ulp of the
/// smaller word per addition (see GeographicLib's Accumulator.hpp). Needs IEEE double arithmetic
/// evaluated as written: -ffast-math (-fassociative-math) would fold the error terms to zero.
#pragma once

#include <cmath>

#ifdef __FAST_MATH__
#error "compensated_sum.hpp needs IEEE arithmetic as written: do not build it with -ffast-math"
#endif

namespace geovor {

class CompensatedSum {
 public:
  CompensatedSum(double y = 0) : s_(y), t_(0) {}  // NOLINT: implicit, as Accumulator's

  CompensatedSum& operator+=(double y) {
    add(y);
    return *this;
  }
  CompensatedSum& operator-=(double y) {
    add(-y);
    return *this;
  }
  CompensatedSum& operator*=(int n) {
    s_ *= n;
    t_ *= n;
    return *this;
  }
  CompensatedSum& operator*=(double) = delete;  // not exact in two words (Accumulator uses fma)
  /// Reduces the sum to [-y/2, y/2] (std::remainder), then renormalizes.
  CompensatedSum& remainder(double y) {
    s_ = std::remainder(s_, y);
    add(0);
    return *this;
  }
  /// The sum.
  double operator()() const { return s_; }
  bool operator<(double y) const { return s_ < y; }
  bool operator<=(double y) const { return s_ <= y; }
  bool operator>(double y) const { return s_ > y; }
  bool operator>=(double y) const { return s_ >= y; }

 private:
  // s + t = u + v exactly, s = round(u + v) (t takes the sign of s when s = 0).
  static double two_sum(double u, double v, double& t) {
    const double s = u + v;
    double up = s - v, vpp = s - up;
    up -= u;
    vpp -= v;
    t = s != 0 ? 0.0 - (up + vpp) : s;
    return s;
  }
  void add(double y) {
    double u;
    y = two_sum(y, t_, u);
    s_ = two_sum(y, s_, t_);
    if (s_ == 0)
      s_ = u;
    else
      t_ += u;
  }
  double s_, t_;
};

}  // namespace geovor
