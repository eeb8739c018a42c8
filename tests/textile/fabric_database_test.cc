// The fabric database (data/fabrics/*.textproto): every file loads and converts to a material.

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "libs/textile/kes_material.h"
#include "tests/textile/fabric_textproto.h"

namespace haptex::textile {
namespace {

TEST(FabricDatabaseTest, EveryFabricConvertsAndCitesASource) {
  int count = 0;
  double lightest = 1e9, heaviest = 0.0, softest_b = 1e9, stiffest_b = 0.0;
  for (const auto& entry : std::filesystem::directory_iterator(testing::SourceDir() + "/data/fabrics")) {
    if (entry.path().extension() != ".textproto") continue;
    const std::string stem = entry.path().stem().string();
    const kes::Fabric f = testing::LoadDatabaseFabric(stem);
    SCOPED_TRACE(stem);
    EXPECT_EQ(f.name, stem);
    EXPECT_FALSE(f.source.citation.empty());
    EXPECT_FALSE(f.source.locator.empty());
    const FabricMaterial m = MaterialFromKes(f);
    EXPECT_GT(m.tensile_warp.Value(0.01), 0.0);
    EXPECT_GT(m.tensile_weft.Value(0.01), 0.0);
    lightest = std::min(lightest, m.density_kg_per_m2);
    heaviest = std::max(heaviest, m.density_kg_per_m2);
    softest_b = std::min(softest_b, m.bending_warp_Nm);
    stiffest_b = std::max(stiffest_b, m.bending_warp_Nm);
    ++count;
  }
  EXPECT_GE(count, 6);
  // Spans light to stiff.
  EXPECT_LT(lightest, 0.15);
  EXPECT_GT(heaviest, 0.3);
  EXPECT_GT(stiffest_b / softest_b, 5.0);
}

}  // namespace
}  // namespace haptex::textile
