// The balanced sites as data: radii and targets on the table, and a CSV that reads back as the
// same weighted sites.
#include "geovor/relax/balanced_sites.hpp"

#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "geovor/geo/site_weights.hpp"
#include "geovor/relax/measure.hpp"
#include "support/file_text.hpp"
#include "support/temp_dir.hpp"

namespace geovor {
namespace {

using testing::slurp;

SiteTable read(const std::string& text) {
  std::istringstream in(text);
  return read_sites_csv(in, "t.csv");
}

// Six sites at the octahedron's vertices, one of them twice (merged), balanced on the sphere.
struct Balanced {
  SiteTable table = read("id,lat,lon,note\nN,90,0,x\nS,-90,0,\n\"a\"\"b\",0,0,y\nE,0,90,z\nW,0,-90,w\nF,0,180,v\n"
                         "E2,0,90,u\n");
  std::vector<Vec3> points = site_points(table);
  BalanceReport result;
  BuildReport build;
  Balanced() {
    const std::vector<double> shares = {1, 1, 2, 1, 1, 1, 1};
    result = balance(points, shares, EllipsoidAreaMeasure());
    (void)balanced_triangulation(points, result, {}, build);
  }
};

TEST(BalancedSites, TheTableCarriesTheRadiiAndTargets) {
  Balanced b;
  ASSERT_TRUE(b.result.converged);
  b.table.sites[1].fields.resize(3);  // a short row (a reader's row always has every field)
  EXPECT_TRUE(apply_balance(b.table, b.result));
  EXPECT_TRUE(b.table.weighted);
  EXPECT_EQ(b.table.columns.back(), "target_m2");
  EXPECT_EQ(b.table.column_types.back(), FieldType::Real);
  for (std::size_t i = 0; i < b.table.sites.size(); ++i) {
    const InputSite& s = b.table.sites[i];
    EXPECT_EQ(s.weight_m, b.result.radii_m[i]);
    ASSERT_EQ(s.fields.size(), b.table.columns.size());  // a short row made whole
    EXPECT_EQ(std::stod(s.fields.back()), b.result.targets[i]);  // 17 digits read back
  }
  EXPECT_EQ(b.table.sites[1].fields[3], "");
}

TEST(BalancedSites, ATableWithATargetColumnKeepsIt) {
  Balanced b;
  b.table.columns[3] = "Target_M2";
  const std::size_t columns = b.table.columns.size();
  EXPECT_FALSE(apply_balance(b.table, b.result));
  EXPECT_EQ(b.table.columns.size(), columns);
  EXPECT_TRUE(b.table.weighted);
  EXPECT_EQ(b.table.sites[0].weight_m, b.result.radii_m[0]);
}

TEST(BalancedSites, TheCsvReadsBackAsTheSameWeightedSites) {
  Balanced b;
  ASSERT_EQ(b.build.merges.size(), 1u);  // E2 into E
  apply_balance(b.table, b.result);
  testing::TempDir dir("geovor_balanced_sites");
  const std::string path = dir / "sites.csv";
  write_balanced_sites(path, false, b.table, b.build, b.result);
  const std::string text = slurp(path);
  EXPECT_EQ(text.substr(0, text.find('\n')), "site_id,lat_deg,lon_deg,weight_m,target_m2");
  EXPECT_NE(text.find("\n\"a\"\"b\",0,0,"), std::string::npos) << text;
  std::istringstream in(text);
  SiteReaderOptions reader;
  reader.id_field = "site_id";
  SiteTable back = read_sites_csv(in, "back.csv", reader);
  read_site_weights(back, "weight_m");
  ASSERT_EQ(back.sites.size(), 6u);  // the merged row is not repeated
  for (std::size_t i = 0; i < back.sites.size(); ++i) {
    EXPECT_EQ(back.sites[i].id, b.table.sites[i].id);
    EXPECT_EQ(back.sites[i].weight_m, b.result.radii_m[i]);
    EXPECT_EQ(back.sites[i].unit, b.table.sites[i].unit);
  }
  EXPECT_THROW(write_balanced_sites(path, false, b.table, b.build, b.result), Error);  // exists
}

}  // namespace
}  // namespace geovor
