#include "libs/textile/grid_mesh.h"

#include <algorithm>
#include <map>
#include <set>
#include <utility>

#include <gtest/gtest.h>

namespace haptex::textile {
namespace {

// Undirected edges of the triangulation, each with the corners opposite it (one per triangle).
std::map<std::pair<int, int>, std::vector<int>> EdgesWithOpposites(const GridMesh& mesh) {
  std::map<std::pair<int, int>, std::vector<int>> edges;
  for (const auto& t : mesh.triangles()) {
    for (int k = 0; k < 3; ++k) {
      const int a = t[static_cast<std::size_t>(k)], b = t[static_cast<std::size_t>((k + 1) % 3)];
      edges[{std::min(a, b), std::max(a, b)}].push_back(t[static_cast<std::size_t>((k + 2) % 3)]);
    }
  }
  return edges;
}

TEST(GridMeshTest, PaperStripHas448Triangles) {
  const GridMesh dut({0.38, 0.20, 17, 15});
  EXPECT_EQ(dut.num_particles(), 255);
  EXPECT_EQ(dut.triangles().size(), 448u);
  EXPECT_NEAR(dut.rest_uv_m(dut.Index(16, 14)).x(), 0.38, 1e-15);
  EXPECT_NEAR(dut.rest_uv_m(dut.Index(16, 14)).y(), 0.20, 1e-15);
}

TEST(GridMeshTest, TrianglesAreCounterClockwiseHalfCells) {
  const GridMesh dut({0.38, 0.20, 17, 15});
  const double half_cell = 0.5 * (0.38 / 16) * (0.20 / 14);
  for (const auto& t : dut.triangles()) {
    for (int q : t) ASSERT_TRUE(q >= 0 && q < dut.num_particles());
    const Eigen::Vector2d e1 = dut.rest_uv_m(t[1]) - dut.rest_uv_m(t[0]);
    const Eigen::Vector2d e2 = dut.rest_uv_m(t[2]) - dut.rest_uv_m(t[0]);
    EXPECT_NEAR(0.5 * (e1.x() * e2.y() - e1.y() * e2.x()), half_cell, 1e-15);
  }
}

TEST(GridMeshTest, BorderQueries) {
  const GridMesh dut({0.1, 0.1, 5, 4});
  const auto border = dut.BorderParticles();
  EXPECT_EQ(border.size(), static_cast<std::size_t>(2 * 5 + 2 * 4 - 4));
  EXPECT_TRUE(dut.IsBorder(dut.Index(0, 0)));
  EXPECT_TRUE(dut.IsBorder(dut.Index(2, 3)));
  EXPECT_FALSE(dut.IsBorder(dut.Index(2, 1)));
}

TEST(GridMeshTest, BorderIsWhereEdgesHaveOneTriangle) {
  const GridMesh dut({0.1, 0.1, 5, 4});
  std::set<int> on_border_edges;
  for (const auto& [edge, opposite] : EdgesWithOpposites(dut)) {
    if (opposite.size() == 1) on_border_edges.insert({edge.first, edge.second});
  }
  const auto border = dut.BorderParticles();
  EXPECT_EQ(std::set<int>(border.begin(), border.end()), on_border_edges);
}

TEST(GridMeshTest, NeighboursOfInteriorParticle) {
  const GridMesh dut({0.1, 0.1, 5, 5});
  const int p = dut.Index(2, 2);
  std::set<int> ring;
  for (const auto& t : dut.triangles()) {
    if (std::find(t.begin(), t.end(), p) == t.end()) continue;
    for (int q : t) {
      if (q != p) ring.insert(q);
    }
  }
  // The four grid neighbours are always in the one-ring.
  for (int q : {dut.Index(1, 2), dut.Index(3, 2), dut.Index(2, 1), dut.Index(2, 3)}) {
    EXPECT_TRUE(ring.count(q)) << q;
  }
  // Plus the diagonal neighbours the triangulation connects: 4 or 8 in total.
  EXPECT_TRUE(ring.size() == 4u || ring.size() == 8u) << ring.size();
}

TEST(GridMeshTest, InteriorEdgesAreSharedByTwoTriangles) {
  const GridMesh dut({0.1, 0.1, 4, 3});
  const auto edges_with_opposites = EdgesWithOpposites(dut);
  const int cells = 3 * 2;
  const int edges = 3 * 3 + 4 * 2 + cells;  // horizontal + vertical + diagonals
  const int boundary = 2 * 3 + 2 * 2;
  EXPECT_EQ(static_cast<int>(edges_with_opposites.size()), edges);
  int interior = 0;
  for (const auto& [edge, opposite] : edges_with_opposites) {
    ASSERT_LE(opposite.size(), 2u);  // a manifold: no edge in three triangles
    if (opposite.size() != 2) continue;
    ++interior;
    EXPECT_NE(opposite[0], opposite[1]);
    for (int q : opposite) EXPECT_TRUE(q != edge.first && q != edge.second);
  }
  EXPECT_EQ(interior, edges - boundary);
}

TEST(GridMeshTest, RejectsBadSpecs) {
  EXPECT_THROW(GridMesh({0.0, 0.1, 3, 3}), std::invalid_argument);
  EXPECT_THROW(GridMesh({0.1, 0.1, 1, 3}), std::invalid_argument);
}

}  // namespace
}  // namespace haptex::textile
