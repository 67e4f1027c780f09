// parse_request_target: the path and the query split and percent-decoded as RFC 3986 and HTML
// forms write them, malformed targets refused; checked against Python's urllib.parse output
// written out by hand below.
#include "request_target.hpp"

#include <gtest/gtest.h>

namespace geovor::service {
namespace {

TEST(RequestTarget, SplitsAndDecodes) {
  const auto t = parse_request_target("/collections/my%20sites/items?bbox=-180%2C-90,180,90&limit=10&name=a+b%2Bc");
  ASSERT_TRUE(t);
  EXPECT_EQ(t->path, "/collections/my sites/items");
  const Params expected = {{"bbox", "-180,-90,180,90"}, {"limit", "10"}, {"name", "a b+c"}};
  EXPECT_EQ(t->query, expected);
}

TEST(RequestTarget, KeepsRepeatedAndEmptyNames) {
  const auto t = parse_request_target("/nearest?k=1&k=2&&flag&=v&lat=");
  ASSERT_TRUE(t);
  EXPECT_EQ(t->path, "/nearest");
  const Params expected = {{"k", "1"}, {"k", "2"}, {"flag", ""}, {"", "v"}, {"lat", ""}};
  EXPECT_EQ(t->query, expected);
  EXPECT_EQ(t->query.count("k"), 2u);
}

TEST(RequestTarget, PlusIsASpaceOnlyInTheQuery) {
  const auto t = parse_request_target("/a+b?x=a+b");
  ASSERT_TRUE(t);
  EXPECT_EQ(t->path, "/a+b");
  EXPECT_EQ(t->query.find("x")->second, "a b");
}

TEST(RequestTarget, DecodesEveryByte) {
  const auto t = parse_request_target("/x?v=%00%ff%C3%A9");
  ASSERT_TRUE(t);
  EXPECT_EQ(t->query.find("v")->second, std::string("\0\xff\xc3\xa9", 4));
}

TEST(RequestTarget, RefusesMalformedTargets) {
  for (const char* bad : {"", "nearest?lat=1", "http://host/nearest", "*", "/x?v=%", "/x?v=%4", "/x?v=%4g", "/%zz", "/x#frag",
                          "/x?v=1%"})
    EXPECT_FALSE(parse_request_target(bad)) << bad;
}

TEST(RequestTarget, NoQueryAndEmptyQuery) {
  EXPECT_TRUE(parse_request_target("/")->query.empty());
  EXPECT_TRUE(parse_request_target("/healthz?")->query.empty());
  EXPECT_EQ(parse_request_target("/healthz?")->path, "/healthz");
}

}  // namespace
}  // namespace geovor::service
