#pragma once
// Rectangular fabric mesh: particles on a (warp u) x (weft v) grid, triangulated, with half-edge
// topology (OpenMesh) for border, one-ring and hinge queries.

#include <array>
#include <vector>

#include <Eigen/Core>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

namespace haptex::textile {

/// Size and resolution of a rectangular fabric.
struct GridSpec {
  double length_warp_m = 0.2;  ///< extent along u (warp)
  double width_weft_m = 0.2;   ///< extent along v (weft)
  int particles_warp = 41;     ///< particles along u (>= 2)
  int particles_weft = 41;     ///< particles along v (>= 2)
};

/// A hinge: interior edge (c, d) shared by triangles (a, c, d) and (b, d, c).
struct Hinge {
  int a = 0, b = 0, c = 0, d = 0;
};

/// Particle grid with rest coordinates and OpenMesh topology. Particle index = i_u + nu * i_v.
class GridMesh {
 public:
  using Mesh = OpenMesh::TriMesh_ArrayKernelT<>;

  /// @throws std::invalid_argument for non-positive or non-finite sizes or fewer than 2x2 particles.
  explicit GridMesh(const GridSpec& spec);

  int num_particles() const { return nu_ * nv_; }
  int particles_warp() const { return nu_; }
  int particles_weft() const { return nv_; }
  int Index(int i_u, int i_v) const { return i_u + nu_ * i_v; }
  /// Rest coordinates (u = warp, v = weft) [m] of particle p.
  const Eigen::Vector2d& rest_uv_m(int p) const { return rest_uv_m_[static_cast<std::size_t>(p)]; }
  const std::vector<std::array<int, 3>>& triangles() const { return triangles_; }

  bool IsBorder(int p) const;
  /// Particles sharing an edge with p, in OpenMesh circulator order.
  std::vector<int> OneRing(int p) const;
  std::vector<int> BorderParticles() const;
  std::vector<Hinge> Hinges() const;
  const Mesh& mesh() const { return mesh_; }

 private:
  int nu_ = 0, nv_ = 0;
  std::vector<Eigen::Vector2d> rest_uv_m_;
  std::vector<std::array<int, 3>> triangles_;
  Mesh mesh_;
};

}  // namespace haptex::textile
