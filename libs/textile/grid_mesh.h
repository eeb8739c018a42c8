#pragma once
// Rectangular fabric mesh: particles on a u x v grid, triangulated. u is the warp and v the weft
// unless ModelOptions::material_angle_rad turns the fabric on the grid. Its topology is
// the grid's own (index arithmetic): no half-edge mesh is needed (docs/fabric-model.md section 3).

#include <array>
#include <vector>

#include <Eigen/Core>

namespace haptex::textile {

/// Size and resolution of a rectangular fabric.
struct GridSpec {
  double length_warp_m = 0.2;  ///< extent along u (warp)
  double width_weft_m = 0.2;   ///< extent along v (weft)
  int particles_warp = 41;     ///< particles along u (>= 2)
  int particles_weft = 41;     ///< particles along v (>= 2)
};

/// Particle grid with rest coordinates and triangles. Particle index = i_u + nu * i_v.
class GridMesh {
 public:
  /// @throws std::invalid_argument for non-positive or non-finite sizes or fewer than 2x2 particles.
  explicit GridMesh(const GridSpec& spec);

  int num_particles() const { return nu_ * nv_; }
  int particles_warp() const { return nu_; }
  int particles_weft() const { return nv_; }
  int Index(int i_u, int i_v) const { return i_u + nu_ * i_v; }
  /// Rest coordinates (u = warp, v = weft) [m] of particle p.
  const Eigen::Vector2d& rest_uv_m(int p) const { return rest_uv_m_[static_cast<std::size_t>(p)]; }
  /// Two per grid cell, counter-clockwise in (u, v); the diagonal alternates cell by cell.
  const std::vector<std::array<int, 3>>& triangles() const { return triangles_; }

  /// Whether p lies on the fabric's edge (first or last row or column of the grid).
  bool IsBorder(int p) const;
  /// Every particle on the fabric's edge, in increasing index.
  std::vector<int> BorderParticles() const;

 private:
  int nu_ = 0, nv_ = 0;
  std::vector<Eigen::Vector2d> rest_uv_m_;
  std::vector<std::array<int, 3>> triangles_;
};

}  // namespace haptex::textile
