// A scripted grasp that visits every contact state of paper Table 1 (I-IX), and the classifier
// names each correctly. Hanging patch in the x-z plane; the thumb on its front (+y, the user's
// side), the index on its back, capsules with their distal axes along x.

#include <algorithm>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "libs/contact/patch_simulation.h"
#include "libs/textile/fabric_model.h"
#include "tests/contact/contact_test_util.h"

namespace haptex::contact {
namespace {

struct Phase {
  const char* what;
  double duration_s;
  Eigen::Vector3d thumb, index;              // targets, reached at 70 % of the phase, then held
  std::optional<ContactState> while_moving;  // checked at 40 % of the phase
  ContactState at_rest;                      // checked at its end
};

TEST(GraspStatesTest, ScriptedGraspVisitsAllNineStates) {
  const textile::FabricMaterial material = testing::DatabaseMaterial("wang2011_black_denim_11oz");
  const double size = 0.03;
  const int n = 21;
  textile::FabricModel model = textile::BuildFabricModel(material, {size, size, n, n});
  textile::Placement placement;
  placement.origin_W = Eigen::Vector3d(-0.5 * size, 0.0, 0.5 * size);
  placement.axis_u_W = Eigen::Vector3d(1, 0, 0);
  placement.axis_v_W = Eigen::Vector3d(0, 0, -1);
  textile::FabricState state = textile::MakeRestState(model, placement);
  for (int p : model.mesh.BorderParticles()) state.Fix(p);
  ContactOptions options;
  options.finger_fabric = {0.4, 0.2};
  options.finger_finger = {0.4, 0.2};
  PatchSimulation sim(std::move(model), std::move(state), testing::LocalStep(), options);

  const double r = options.thumb.radius_m + options.fabric_half_thickness_m;
  const double R = options.thumb.radius_m;
  using V = Eigen::Vector3d;
  const V thumb_away(0.0, r + 0.01, 0.004), index_away(0.0, -r - 0.01, -0.007);
  const V beside(0.045, 0.0, 0.0);  // beyond the patch's edge: the fingers meet in free air
  const std::vector<Phase> phases = {
      {"apart", 0.2, thumb_away, index_away, ContactState::kI, ContactState::kI},
      {"to the side", 0.4, beside + V(0, R + 0.002, 0), beside - V(0, R + 0.002, 0), ContactState::kI,
       ContactState::kI},
      {"fingers touch", 0.3, beside + V(0, R - 0.0004, 0), beside - V(0, R - 0.0004, 0), ContactState::kI,
       ContactState::kII},
      {"fingers rub", 0.4, beside + V(0, R - 0.0004, 0.004), beside - V(0, R - 0.0004, 0), ContactState::kIII,
       ContactState::kII},
      {"fingers part", 0.3, thumb_away, index_away, ContactState::kI, ContactState::kI},
      {"thumb presses", 0.4, V(0, r - 0.002, 0.004), index_away, std::nullopt, ContactState::kIV},
      {"thumb rubs", 0.6, V(0.006, r - 0.002, 0.004), index_away, ContactState::kV, ContactState::kIV},
      {"index presses", 0.4, V(0.006, r - 0.002, 0.004), V(0.0, -(r - 0.002), -0.007), std::nullopt, ContactState::kVI},
      {"both rub", 0.6, V(0.0, r - 0.002, 0.004), V(0.006, -(r - 0.002), -0.007), ContactState::kVII,
       ContactState::kVI},
      {"index to thumb", 0.6, V(0.0, r - 0.002, 0.004), V(0.0, -(r - 0.002), 0.004), std::nullopt, ContactState::kVIII},
      {"squeeze", 0.3, V(0.0, r - 0.0035, 0.004), V(0.0, -(r - 0.0035), 0.004), ContactState::kVIII,
       ContactState::kVIII},
      {"pinch slides", 0.8, V(0.0, r - 0.0035, -0.006), V(0.0, -(r - 0.0035), -0.006), ContactState::kIX,
       ContactState::kVIII},
      {"release", 0.4, thumb_away, index_away, ContactState::kI, ContactState::kI},
  };

  std::vector<ContactState> visited;
  V thumb = thumb_away, index = index_away;
  const double dt = sim.dt_s();
  for (const Phase& ph : phases) {
    const V thumb0 = thumb, index0 = index;
    const int ticks = static_cast<int>(ph.duration_s / dt + 0.5);
    for (int k = 1; k <= ticks; ++k) {
      const double s = std::min(1.0, k / (0.7 * ticks));
      thumb = thumb0 + s * (ph.thumb - thumb0);
      index = index0 + s * (ph.index - index0);
      const ContactOutput& out = sim.Tick({true, testing::PoseFacing(thumb, V(0, -1, 0), V::UnitX())},
                                          {true, testing::PoseFacing(index, V(0, 1, 0), V::UnitX())});
      if (visited.empty() || visited.back() != out.state) visited.push_back(out.state);
      ASSERT_TRUE(out.finger[kThumb].force_W_N.allFinite());
      if (k == static_cast<int>(0.4 * ticks) && ph.while_moving) {
        EXPECT_EQ(ToString(out.state), std::string(ToString(*ph.while_moving))) << ph.what << " (moving)";
      }
      if (k == ticks) {
        EXPECT_EQ(ToString(out.state), std::string(ToString(ph.at_rest))) << ph.what << " (at rest)";
        std::printf("[grasp] %-15s state %-4s thumb %.3f N index %.3f N grip %.3f N samples %d\n", ph.what,
                    ToString(out.state), out.finger[kThumb].force_W_N.norm(), out.finger[kIndex].force_W_N.norm(),
                    out.pinch.grip_N, out.pinch.samples);
      }
    }
  }
  std::string path;
  for (ContactState s : visited) path += std::string(ToString(s)) + " ";
  std::printf("[grasp] visited: %s\n", path.c_str());
  for (int s = 1; s <= 9; ++s) {
    EXPECT_NE(std::find(visited.begin(), visited.end(), static_cast<ContactState>(s)), visited.end())
        << "never visited " << ToString(static_cast<ContactState>(s));
  }
}

}  // namespace
}  // namespace haptex::contact
