#include "libs/dual_layer/patch_data.h"

#include <cmath>

namespace haptex::dual_layer {

PatchData::PatchData(int max_particles) {
  const auto n = static_cast<std::size_t>(max_particles);
  ids.reserve(n);
  rest_uv_m.reserve(2 * n);
  x_W_m.reserve(3 * n);
  v_W_m_per_s.reserve(3 * n);
  mass_kg.reserve(n);
  border.reserve(n);
  triangles.reserve(6 * n);
}

void PatchData::Clear() {
  num_particles = 0;
  ids.clear();
  rest_uv_m.clear();
  x_W_m.clear();
  v_W_m_per_s.clear();
  mass_kg.clear();
  border.clear();
  triangles.clear();
}

bool IsBuildable(const PatchData& patch, std::uint32_t max_particle_id) {
  const auto n = static_cast<std::size_t>(patch.num_particles);
  if (patch.num_particles < 4 || patch.ids.size() != n || patch.rest_uv_m.size() != 2 * n ||
      patch.x_W_m.size() != 3 * n || patch.v_W_m_per_s.size() != 3 * n || patch.border.size() != n ||
      !(patch.global_dt_s > 0.0) || !std::isfinite(patch.global_dt_s)) {
    return false;
  }
  for (std::uint32_t id : patch.ids) {
    if (id >= max_particle_id) return false;
  }
  for (double v : patch.rest_uv_m) {
    if (!std::isfinite(v)) return false;
  }
  for (std::size_t k = 0; k < 3 * n; ++k) {
    if (!std::isfinite(patch.x_W_m[k]) || !std::isfinite(patch.v_W_m_per_s[k])) return false;
  }
  return true;
}

}  // namespace haptex::dual_layer
