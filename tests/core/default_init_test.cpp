/// \file default_init_test.cpp
/// \brief DefaultInitAllocator: a vector with it behaves as any vector once its elements are
/// written (resize() alone leaves trivial elements unwritten, which no test may read).
#include "geovor/core/default_init.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

namespace geovor {
namespace {

TEST(DefaultInitAllocator, VectorFilledAfterResizeKeepsItsValues) {
  std::vector<std::uint32_t, DefaultInitAllocator<std::uint32_t>> v;
  v.resize(1000);
  for (std::uint32_t i = 0; i < v.size(); ++i) v[i] = 3 * i;
  v.resize(1500, 7);  // with a value: those elements are that value
  v.push_back(42);
  const auto copy = v;
  ASSERT_EQ(copy.size(), 1501u);
  for (std::uint32_t i = 0; i < 1000; ++i) ASSERT_EQ(copy[i], 3 * i);
  for (std::uint32_t i = 1000; i < 1500; ++i) ASSERT_EQ(copy[i], 7u);
  EXPECT_EQ(copy.back(), 42u);
}

}  // namespace
}  // namespace geovor
