#include "libs/contact/anchor_accumulator.h"

namespace haptex::contact {

void AnchorAccumulator::WriteTo(textile::FabricState* state) const {
  const int n = static_cast<int>(k_.size());
  if (state->anchor_stiffness_N_per_m.size() != n) state->anchor_stiffness_N_per_m.resize(n);
  if (state->anchor_W_m.size() != 3 * n) state->anchor_W_m.resize(3 * n);
  // Every particle without a spring (k = 0) keeps its anchor at itself; then the touched ones.
  state->anchor_stiffness_N_per_m = k_;
  state->anchor_W_m = state->x_W_m;
  for (int i = 0; i < num_touched_; ++i) {
    const int p = touched_[static_cast<std::size_t>(i)];
    const double k = k_[p];
    if (k > 0.0) state->anchor_W_m.segment<3>(3 * p) = ka_.segment<3>(3 * p) / k;
  }
}

}  // namespace haptex::contact
