#include "services/local_contact/patch_data.h"

#include <cmath>

namespace haptex::local_contact {

PatchData::PatchData(int max_particles) {
  const auto n = static_cast<std::size_t>(max_particles);
  ids.reserve(n);
  rest_uv_m.reserve(2 * n);
  x_W_m.reserve(3 * n);
  v_W_m_per_s.reserve(3 * n);
  border.reserve(n);
}

PatchData::Copy PatchData::CopyFrom(const v1::LocalPatch& patch, std::uint32_t max_particle_id) {
  const int n = patch.particle_ids_size();
  if (static_cast<std::size_t>(n) > ids.capacity()) return Copy::kTooLarge;
  if (n < 4 || patch.rest_uv_m_size() != 2 * n || patch.position_w_m_size() != 3 * n ||
      patch.velocity_w_m_per_s_size() != 3 * n || patch.is_border_size() != n ||
      !(patch.global_dt_s() > 0.0) || !std::isfinite(patch.global_dt_s())) {
    return Copy::kMalformed;
  }
  ids.clear();
  rest_uv_m.clear();
  x_W_m.clear();
  v_W_m_per_s.clear();
  border.clear();
  for (int k = 0; k < n; ++k) {
    if (patch.particle_ids(k) >= max_particle_id) return Copy::kMalformed;
    ids.push_back(patch.particle_ids(k));
    border.push_back(patch.is_border(k) ? 1 : 0);
  }
  for (double v : patch.rest_uv_m()) {
    if (!std::isfinite(v)) return Copy::kMalformed;
    rest_uv_m.push_back(v);
  }
  for (int k = 0; k < 3 * n; ++k) {
    const double x = patch.position_w_m(k), v = patch.velocity_w_m_per_s(k);
    if (!std::isfinite(x) || !std::isfinite(v)) return Copy::kMalformed;
    x_W_m.push_back(x);
    v_W_m_per_s.push_back(v);
  }
  patch_id = patch.patch_id();
  global_dt_s = patch.global_dt_s();
  num_particles = n;
  return Copy::kOk;
}

}  // namespace haptex::local_contact
