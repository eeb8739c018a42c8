#include "libs/dual_layer/patch_result.h"

namespace haptex::dual_layer {

PatchResultData::PatchResultData(int max_particles) {
  const auto n = static_cast<std::size_t>(max_particles);
  ids.reserve(n);
  x_W_m.reserve(3 * n);
  v_W_m_per_s.reserve(3 * n);
  external_force_W_N.reserve(3 * n);
}

void PatchResultData::Clear() {
  ids.clear();
  x_W_m.clear();
  v_W_m_per_s.clear();
  external_force_W_N.clear();
}

}  // namespace haptex::dual_layer
