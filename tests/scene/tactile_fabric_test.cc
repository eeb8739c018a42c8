#include "libs/scene/tactile_fabric.h"

#include <gtest/gtest.h>

#include <Eigen/LU>

namespace haptex::scene {
namespace {

TEST(TactileFabricTest, MissingSurfaceDataIsListedNotInvented) {
  v1::Fabric fabric;
  fabric.set_name("bare");
  try {
    TactileWeave(fabric, {});
    FAIL();
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    for (const char* item : {"weave pattern", "warp pitch", "weft pitch", "yarn diameter", "SMD"}) {
      EXPECT_NE(what.find(item), std::string::npos) << item << " in: " << what;
    }
  }
}

TEST(TactileFabricTest, FabricValuesAndOverridesCombine) {
  v1::Fabric fabric;
  fabric.mutable_weave()->set_pattern(v1::Weave::PATTERN_TWILL);
  fabric.mutable_weave()->set_warp_pitch_mm(0.5);
  fabric.mutable_weave()->set_weft_pitch_mm(0.5);
  fabric.mutable_weave()->set_yarn_diameter_mm(0.3);
  fabric.mutable_surface()->set_smd_um(3.6);
  TactileSurfaceOverrides overrides;
  overrides.weft_pitch_mm = 0.6;
  const tactile::WeaveParams weave = TactileWeave(fabric, overrides);
  EXPECT_EQ(weave.pattern, tactile::WeavePattern::kTwill);
  EXPECT_DOUBLE_EQ(weave.warp_pitch_m, 0.5e-3);
  EXPECT_DOUBLE_EQ(weave.weft_pitch_m, 0.6e-3);
  EXPECT_DOUBLE_EQ(weave.smd_um, 3.6);
  overrides.pattern = "basket";
  EXPECT_THROW(TactileWeave(fabric, overrides), std::invalid_argument);
}

TEST(TactileFabricTest, HandValuesOverTheScenesOverTheFabrics) {
  v1::Fabric fabric;
  fabric.mutable_weave()->set_pattern(v1::Weave::PATTERN_PLAIN);
  fabric.mutable_weave()->set_warp_pitch_mm(0.5);
  fabric.mutable_weave()->set_yarn_diameter_mm(0.3);
  v1::TactileSurface scene_surface;
  scene_surface.set_pattern(v1::Weave::PATTERN_TWILL);
  scene_surface.set_warp_pitch_mm(0.42);
  scene_surface.set_weft_pitch_mm(0.64);
  scene_surface.set_smd_um(3.5);
  TactileSurfaceOverrides by_hand;
  by_hand.smd_um = 5;
  const tactile::WeaveParams weave = TactileWeave(fabric, WithSceneSurface(scene_surface, by_hand));
  EXPECT_EQ(weave.pattern, tactile::WeavePattern::kTwill);
  EXPECT_DOUBLE_EQ(weave.warp_pitch_m, 0.42e-3);
  EXPECT_DOUBLE_EQ(weave.weft_pitch_m, 0.64e-3);
  EXPECT_DOUBLE_EQ(weave.yarn_diameter_m, 0.3e-3);  // the fabric's: neither the scene nor the hand gives it
  EXPECT_DOUBLE_EQ(weave.smd_um, 5.0);
}

TEST(TactileFabricTest, TileRepeatsWithTheThreadPitch) {
  v1::Fabric fabric;
  TactileSurfaceOverrides o;
  o.pattern = "plain";
  o.warp_pitch_mm = o.weft_pitch_mm = 0.8;
  o.yarn_diameter_mm = 0.5;
  o.smd_um = 4;
  const VirtualFabric v = BuildVirtualFabric(fabric, o);
  // a plain weave repeats every two threads in each direction
  const Eigen::Matrix2d basis = v.tile.basis_m();
  const double area = std::abs(basis.determinant());
  EXPECT_NEAR(area, (2 * 0.8e-3) * (2 * 0.8e-3), 0.05 * area) << basis;
}

}  // namespace
}  // namespace haptex::scene
