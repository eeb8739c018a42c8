// The patch global_sim cuts for local_contact: the rectangle around the fingers' spheres, its
// border ring, and its refinement (every cell split, ids stable across patches).
#include "libs/dual_layer/patch_cut.h"

#include <gtest/gtest.h>

#include <set>

#include <map>

#include "libs/textile/kes_material.h"
#include "tests/textile/textile_test_util.h"

namespace haptex::dual_layer {
namespace {

textile::FabricMaterial Material() { return textile::MaterialFromKes(textile::testing::CompositeDenim()); }

struct Cloth {
  textile::FabricModel model;
  textile::FabricState state;
};

// 11 x 9 particles, 1 cm apart, lying in the x-y plane with a wrinkle in z; top row fixed.
Cloth MakeCloth() {
  Cloth c{textile::BuildFabricModel(Material(), {0.10, 0.08, 11, 9}), {}};
  c.state = textile::MakeRestState(c.model);
  for (int p = 0; p < c.model.num_particles; ++p) {
    c.state.x_W_m[3 * p + 2] = 0.003 * std::sin(40.0 * c.state.x_W_m[3 * p]);
    c.state.v_W_m_per_s[3 * p + 1] = 0.01 * p;
  }
  for (int i = 0; i < 11; ++i) c.state.Fix(c.model.mesh.Index(i, 0));
  return c;
}

std::array<FingerSphere, 2> SphereAt(const Eigen::Vector3d& centre_W_m, double radius_m) {
  std::array<FingerSphere, 2> s{};
  s[0].present = true;
  s[0].centre_W_m = centre_W_m;
  s[0].radius_m = radius_m;
  return s;
}

TEST(PatchCutTest, RectangleCoversTheSphereWithABorderRingOnAnEvenCell) {
  const Cloth c = MakeCloth();
  const PatchRect r = FindPatchRect(c.model, c.state, SphereAt({0.05, 0.04, 0.0}, 0.011));
  ASSERT_FALSE(r.empty());
  // particles within 1.1 cm of (5, 4) cm: i 4..6, j 3..5; one ring more, then an even corner
  EXPECT_LE(r.i0, 3);
  EXPECT_GE(r.i1, 7);
  EXPECT_LE(r.j0, 2);
  EXPECT_GE(r.j1, 6);
  EXPECT_EQ((r.i0 + r.j0) % 2, 0);
  EXPECT_TRUE(FindPatchRect(c.model, c.state, SphereAt({1.0, 1.0, 1.0}, 0.01)).empty());
}

TEST(PatchCutTest, UnrefinedPatchIsTheFabricsOwnParticles) {
  const Cloth c = MakeCloth();
  const PatchRect r{2, 6, 0, 4};
  PatchData patch;
  CutPatch(c.model, c.state, c.state.v_W_m_per_s, r, 7, 3, 0.01, MakeRefinedGrid(11, 9, 0), &patch);
  ASSERT_EQ(patch.num_particles, 25);
  EXPECT_EQ(static_cast<int>(patch.triangles.size()), 3 * 2 * 16);
  for (int k = 0; k < 25; ++k) {
    const int i = 2 + k % 5, j = k / 5;
    const int p = c.model.mesh.Index(i, j);
    EXPECT_EQ(patch.ids[k], static_cast<std::uint32_t>(p));
    EXPECT_DOUBLE_EQ(patch.x_W_m[3 * k + 2], c.state.x_W_m[3 * p + 2]);
    EXPECT_DOUBLE_EQ(patch.mass_kg[k], c.model.mass_kg[p]);
    // border: the rectangle's left, right and bottom edges (inside the fabric) and the fixed top row
    const bool border = i == 2 || i == 6 || j == 4 || j == 0;
    EXPECT_EQ(patch.border[k] != 0, border) << i << "," << j;
  }
  // the same triangles as the fabric's cells (2, 0) .. (5, 3), split the same way
  std::set<std::array<std::uint32_t, 3>> fabric_tris;
  for (const auto& t : c.model.mesh.triangles()) {
    fabric_tris.insert(
        {static_cast<std::uint32_t>(t[0]), static_cast<std::uint32_t>(t[1]), static_cast<std::uint32_t>(t[2])});
  }
  for (int t = 0; t < static_cast<int>(patch.triangles.size()) / 3; ++t) {
    std::array<std::uint32_t, 3> global{};
    for (int k = 0; k < 3; ++k)
      global[static_cast<std::size_t>(k)] = patch.ids[static_cast<int>(patch.triangles[3 * t + k])];
    EXPECT_TRUE(fabric_tris.count(global)) << "triangle " << t;
  }
}

TEST(PatchCutTest, RefinedPatchSplitsEveryCellAndKeepsIdsAcrossPatches) {
  const Cloth c = MakeCloth();
  const RefinedGrid grid = MakeRefinedGrid(11, 9, 1);
  PatchData a, b;
  CutPatch(c.model, c.state, c.state.v_W_m_per_s, PatchRect{2, 6, 0, 4}, 1, 1, 0.01, grid, &a);
  CutPatch(c.model, c.state, c.state.v_W_m_per_s, PatchRect{4, 8, 2, 6}, 2, 2, 0.01, grid, &b);
  ASSERT_EQ(a.num_particles, 9 * 9);
  EXPECT_EQ(static_cast<int>(a.triangles.size()), 3 * 2 * 64);
  std::set<std::uint32_t> ids(a.ids.begin(), a.ids.end());
  EXPECT_EQ(ids.size(), 81u) << "ids are unique";
  double mass = 0.0;
  for (int k = 0; k < 81; ++k) {
    const int I = 4 + k % 9, J = k / 9;  // refined grid point
    const std::uint32_t id = a.ids[k];
    EXPECT_LT(id, grid.id_space());
    if (I % 2 == 0 && J % 2 == 0) {
      const int p = c.model.mesh.Index(I / 2, J / 2);
      EXPECT_EQ(id, static_cast<std::uint32_t>(p));
      EXPECT_DOUBLE_EQ(a.x_W_m[3 * k + 2], c.state.x_W_m[3 * p + 2]);
    } else {
      EXPECT_GE(id, static_cast<std::uint32_t>(c.model.num_particles));
      // the bilinear blend of its cell: rest coordinates halfway, position the corners' mean
      EXPECT_NEAR(a.rest_uv_m[2 * k], 0.005 * I, 1e-12);
      EXPECT_NEAR(a.rest_uv_m[2 * k + 1], 0.005 * J, 1e-12);
      const int i = I / 2, j = J / 2;
      const int di = I % 2, dj = J % 2;
      double z = 0.0, vy = 0.0;
      int corners = 0;
      for (int cj = j; cj <= j + dj; ++cj) {
        for (int ci = i; ci <= i + di; ++ci) {
          z += c.state.x_W_m[3 * c.model.mesh.Index(ci, cj) + 2];
          vy += c.state.v_W_m_per_s[3 * c.model.mesh.Index(ci, cj) + 1];
          ++corners;
        }
      }
      EXPECT_NEAR(a.x_W_m[3 * k + 2], z / corners, 1e-12);
      EXPECT_NEAR(a.v_W_m_per_s[3 * k + 1], vy / corners, 1e-12);
    }
    // the fixed top row stays fixed between its particles; the rectangle's other edges are border
    const bool border = I == 4 || I == 12 || J == 8 || J == 0;
    EXPECT_EQ(a.border[k] != 0, border) << I << "," << J;
    mass += a.mass_kg[k];
  }
  // each particle's lumped mass in the refined fabric (a quarter of each refined cell around it):
  // the patch owns half a refined cell beyond its inner edges, nothing beyond the fabric's top edge
  EXPECT_NEAR(mass, Material().density_kg_per_m2 * (0.04 + 0.005) * (0.04 + 0.0025), 1e-12);
  // the other patch names the shared refined points alike
  std::map<std::pair<double, double>, std::uint32_t> id_at;
  for (int k = 0; k < 81; ++k) id_at[{a.rest_uv_m[2 * k], a.rest_uv_m[2 * k + 1]}] = a.ids[k];
  int shared = 0;
  for (int k = 0; k < b.num_particles; ++k) {
    const auto it = id_at.find({b.rest_uv_m[2 * k], b.rest_uv_m[2 * k + 1]});
    if (it == id_at.end()) continue;
    EXPECT_EQ(it->second, b.ids[k]);
    ++shared;
  }
  EXPECT_EQ(shared, 5 * 5);
}

TEST(PatchCutTest, RefinementLevelsAreBounded) {
  EXPECT_THROW(MakeRefinedGrid(11, 9, 5), std::invalid_argument);
  EXPECT_THROW(MakeRefinedGrid(1, 9, 0), std::invalid_argument);
  EXPECT_EQ(MakeRefinedGrid(11, 9, 2).fine_u, 41);
}

}  // namespace
}  // namespace haptex::dual_layer
