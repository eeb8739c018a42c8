#include "libs/contact/anchor_accumulator.h"

namespace haptex::contact {

void AnchorAccumulator::WriteTo(textile::FabricState* state) const {
  const int n = static_cast<int>(k_.size());
  if (state->anchor_stiffness_N_per_m.size() != n) state->anchor_stiffness_N_per_m.resize(n);
  if (state->anchor_W_m.size() != 3 * n) state->anchor_W_m.resize(3 * n);
  for (int p = 0; p < n; ++p) {
    const double k = k_[p];
    state->anchor_stiffness_N_per_m[p] = k;
    state->anchor_W_m.segment<3>(3 * p) =
        k > 0.0 ? Eigen::Vector3d(ka_.segment<3>(3 * p) / k) : state->x_W_m.segment<3>(3 * p);
  }
}

}  // namespace haptex::contact
