#include "libs/textile/grid_mesh.h"

#include <cmath>
#include <stdexcept>

namespace haptex::textile {

GridMesh::GridMesh(const GridSpec& spec) : nu_(spec.particles_warp), nv_(spec.particles_weft) {
  if (!(std::isfinite(spec.length_warp_m) && spec.length_warp_m > 0.0)) {
    throw std::invalid_argument("GridSpec.length_warp_m must be finite and > 0");
  }
  if (!(std::isfinite(spec.width_weft_m) && spec.width_weft_m > 0.0)) {
    throw std::invalid_argument("GridSpec.width_weft_m must be finite and > 0");
  }
  if (nu_ < 2 || nv_ < 2) {
    throw std::invalid_argument("GridSpec needs at least 2 particles along warp and weft");
  }
  const double du = spec.length_warp_m / (nu_ - 1);
  const double dv = spec.width_weft_m / (nv_ - 1);
  rest_uv_m_.reserve(static_cast<std::size_t>(nu_ * nv_));
  for (int j = 0; j < nv_; ++j) {
    for (int i = 0; i < nu_; ++i) rest_uv_m_.emplace_back(i * du, j * dv);
  }
  // Alternate the diagonal cell by cell so the triangulation has no preferred bias direction.
  for (int j = 0; j + 1 < nv_; ++j) {
    for (int i = 0; i + 1 < nu_; ++i) {
      const int p00 = Index(i, j), p10 = Index(i + 1, j), p01 = Index(i, j + 1), p11 = Index(i + 1, j + 1);
      if ((i + j) % 2 == 0) {
        triangles_.push_back({p00, p10, p11});
        triangles_.push_back({p00, p11, p01});
      } else {
        triangles_.push_back({p00, p10, p01});
        triangles_.push_back({p10, p11, p01});
      }
    }
  }
}

bool GridMesh::IsBorder(int p) const {
  const int i_u = p % nu_, i_v = p / nu_;
  return i_u == 0 || i_u == nu_ - 1 || i_v == 0 || i_v == nv_ - 1;
}

std::vector<int> GridMesh::BorderParticles() const {
  std::vector<int> out;
  for (int p = 0; p < num_particles(); ++p) {
    if (IsBorder(p)) out.push_back(p);
  }
  return out;
}

}  // namespace haptex::textile
