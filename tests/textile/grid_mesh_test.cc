#include "libs/textile/grid_mesh.h"

#include <algorithm>
#include <set>

#include <gtest/gtest.h>

namespace haptex::textile {
namespace {

TEST(GridMeshTest, PaperStripHas448Triangles) {
  const GridMesh dut({0.38, 0.20, 17, 15});
  EXPECT_EQ(dut.num_particles(), 255);
  EXPECT_EQ(dut.triangles().size(), 448u);
  EXPECT_EQ(dut.mesh().n_faces(), 448u);
  EXPECT_NEAR(dut.rest_uv_m(dut.Index(16, 14)).x(), 0.38, 1e-15);
  EXPECT_NEAR(dut.rest_uv_m(dut.Index(16, 14)).y(), 0.20, 1e-15);
}

TEST(GridMeshTest, BorderQueries) {
  const GridMesh dut({0.1, 0.1, 5, 4});
  const auto border = dut.BorderParticles();
  EXPECT_EQ(border.size(), static_cast<std::size_t>(2 * 5 + 2 * 4 - 4));
  EXPECT_TRUE(dut.IsBorder(dut.Index(0, 0)));
  EXPECT_TRUE(dut.IsBorder(dut.Index(2, 3)));
  EXPECT_FALSE(dut.IsBorder(dut.Index(2, 1)));
}

TEST(GridMeshTest, OneRingOfInteriorParticle) {
  const GridMesh dut({0.1, 0.1, 5, 5});
  const int p = dut.Index(2, 2);
  auto ring = dut.OneRing(p);
  std::set<int> s(ring.begin(), ring.end());
  // The four grid neighbours are always in the one-ring.
  for (int q : {dut.Index(1, 2), dut.Index(3, 2), dut.Index(2, 1), dut.Index(2, 3)}) {
    EXPECT_TRUE(s.count(q)) << q;
  }
  // Plus the diagonal neighbours the triangulation connects: 4 or 8 in total.
  EXPECT_TRUE(ring.size() == 4u || ring.size() == 8u) << ring.size();
}

TEST(GridMeshTest, HingesAreInteriorEdges) {
  const GridMesh dut({0.1, 0.1, 4, 3});
  const auto hinges = dut.Hinges();
  // Edges: 3*2 cells * 3 + (3 + 2) borders... interior = total - boundary.
  const int cells = 3 * 2;
  const int edges = 3 * 3 + 4 * 2 + cells;  // horizontal + vertical + diagonals
  const int boundary = 2 * 3 + 2 * 2;
  EXPECT_EQ(static_cast<int>(hinges.size()), edges - boundary);
  for (const auto& h : hinges) {
    EXPECT_NE(h.a, h.b);
    for (int q : {h.a, h.b}) EXPECT_TRUE(q != h.c && q != h.d);
  }
}

TEST(GridMeshTest, RejectsBadSpecs) {
  EXPECT_THROW(GridMesh({0.0, 0.1, 3, 3}), std::invalid_argument);
  EXPECT_THROW(GridMesh({0.1, 0.1, 1, 3}), std::invalid_argument);
}

}  // namespace
}  // namespace haptex::textile
