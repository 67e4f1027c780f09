/// \file fuzz_bytes.hpp
/// \brief Bytes: a fuzz input read as little-endian integers and ranged doubles; past its end,
/// zeros (so every input decodes to something). Reads are sequenced one per statement or
/// declarator: the order of a call's arguments is unspecified (gcc reads right to left, clang
/// left to right), and one input must decode to the same sites in every build.
#pragma once

#include <cstddef>
#include <cstdint>

class Bytes {
 public:
  Bytes(const std::uint8_t* d, std::size_t n) : d_(d), n_(n) {}
  bool empty() const { return i_ >= n_; }
  std::uint8_t u8() { return i_ < n_ ? d_[i_++] : 0; }
  std::uint16_t u16() {
    const unsigned lo = u8();  // sequenced: the operands of | are not
    return static_cast<std::uint16_t>(lo | (unsigned{u8()} << 8));
  }
  std::uint64_t u64() {
    std::uint64_t v = 0;
    for (int k = 0; k < 8; ++k) v |= std::uint64_t{u8()} << (8 * k);
    return v;
  }
  // In [lo, hi], 65536 steps.
  double range(double lo, double hi) { return lo + (hi - lo) * (u16() / 65535.0); }

 private:
  const std::uint8_t* d_;
  std::size_t n_, i_ = 0;
};
