#include "libs/scene/fabric_conversion.h"

#include <gtest/gtest.h>

#include "libs/scene/fabric_database.h"
#include "tests/scene/scene_test_support.h"

namespace haptex::scene {
namespace {

TEST(FabricConversionTest, CopiesEveryValueInKesUnits) {
  v1::Fabric f = FabricDatabase(testing::TestDataDir() + "/fabrics").Load("test_cotton");
  f.mutable_warp_tensile()->add_loading_curve()->set_x(0.01);
  f.mutable_warp_tensile()->mutable_loading_curve(0)->set_y(20.0);
  f.mutable_weave()->set_pattern(v1::Weave::PATTERN_TWILL);
  f.mutable_surface()->set_smd_um(3.5);
  f.add_flags()->set_field("weight_mg_per_cm2");
  const textile::kes::Fabric k = ToKesFabric(f);
  EXPECT_EQ(k.name, "test_cotton");
  EXPECT_DOUBLE_EQ(k.warp_tensile.emt_percent, 5.0);
  EXPECT_DOUBLE_EQ(k.weft_tensile.emt_percent, 6.0);
  EXPECT_DOUBLE_EQ(k.warp_tensile.lt, 0.7);
  ASSERT_EQ(k.warp_tensile.loading_curve.size(), 1u);
  EXPECT_DOUBLE_EQ(k.warp_tensile.loading_curve[0].y, 20.0);
  EXPECT_DOUBLE_EQ(k.shear.g_gf_per_cm_deg, 1.0);
  EXPECT_DOUBLE_EQ(k.warp_bending.b_gfcm2_per_cm, 0.1);
  EXPECT_DOUBLE_EQ(k.weft_bending.b_gfcm2_per_cm, 0.08);
  EXPECT_DOUBLE_EQ(k.thickness_mm, 0.5);
  EXPECT_DOUBLE_EQ(k.weight_mg_per_cm2, 15.0);
  EXPECT_DOUBLE_EQ(k.surface.smd_um, 3.5);
  EXPECT_EQ(k.weave.pattern, textile::kes::Weave::Pattern::kTwill);
  ASSERT_EQ(k.flags.size(), 1u);
  EXPECT_EQ(k.flags[0].field, "weight_mg_per_cm2");
}

TEST(FabricConversionTest, LoadsADatabaseFabricValidatedAndConverted) {
  const FabricDatabase db(testing::TestDataDir() + "/fabrics");
  const textile::kes::Fabric k = LoadKesFabric(db, "test_cotton");
  EXPECT_EQ(k.name, "test_cotton");
  EXPECT_DOUBLE_EQ(k.warp_tensile.emt_percent, 5.0);
  EXPECT_DOUBLE_EQ(k.weight_mg_per_cm2, 15.0);
  EXPECT_THROW(LoadKesFabric(db, "no_such_fabric"), std::exception);
}

}  // namespace
}  // namespace haptex::scene
