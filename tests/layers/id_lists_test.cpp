#include "geovor/layers/id_lists.hpp"

#include <gtest/gtest.h>

#include <string>

namespace geovor {
namespace {

std::string element(std::string_view id) {
  std::string out;
  append_id_list_element(out, id);
  return out;
}

TEST(IdLists, ElementIsTheIdAsAJsonString) {
  EXPECT_EQ(element("KSEA"), R"("KSEA")");
  EXPECT_EQ(element("q\"uote"), R"("q\"uote")");
  EXPECT_EQ(element("back\\slash"), R"("back\\slash")");
  EXPECT_EQ(element("tab\tid"), R"("tab\tid")");
  EXPECT_EQ(element("new\nline\x1f"), R"("new\nline\u001f")");
  EXPECT_EQ(element("Z\xc3\xbcrich"), "\"Z\xc3\xbcrich\"");  // UTF-8 as it is
  EXPECT_EQ(element("bad\xff"), "\"bad\xef\xbf\xbd\"");  // not UTF-8: U+FFFD, as in site_id
  EXPECT_EQ(element(""), R"("")");
}

SiteTable table_of(const std::vector<std::string>& ids) {
  SiteTable table;
  for (const std::string& id : ids) {
    InputSite site;
    site.id = id;
    table.sites.push_back(site);
  }
  return table;
}

TEST(IdLists, CellIdTextsOfEveryRow) {
  const CellIdTexts texts = make_cell_id_texts(table_of({"a", "q\"uote", "tab\tid", "bad\xff"}), 1);
  ASSERT_EQ(texts.text.size(), 4u);
  EXPECT_EQ(texts.text[0], R"("a")");
  EXPECT_EQ(texts.text[1], R"("q\"uote")");
  EXPECT_EQ(texts.text[2], R"("tab\tid")");  // the feature's own string: append_json_string
  EXPECT_EQ(texts.text[3], "\"bad\xef\xbf\xbd\"");  // GeoJSON is UTF-8: U+FFFD
}

TEST(IdLists, CellIdTextsOnSeveralThreadsSurviveAMove) {
  std::vector<std::string> ids;
  for (int i = 0; i < 20000; ++i) ids.push_back(std::string(1, 'r') += std::to_string(i));
  CellIdTexts moved = make_cell_id_texts(table_of(ids), 4);
  const CellIdTexts texts = std::move(moved);
  ASSERT_EQ(texts.text.size(), ids.size());
  for (std::size_t i = 0; i < ids.size(); i += 997) {
    EXPECT_EQ(texts.text[i], "\"" + ids[i] + "\"");
  }
  EXPECT_EQ(texts.text.back(), "\"r19999\"");
}

}  // namespace
}  // namespace geovor
