#include "libs/textile/anchor_spring_force.h"

#include <algorithm>

namespace haptex::textile {

void AddAnchorSpringForces(const FabricModel& model, const FabricState& state, ForceSink* sink) {
  if (state.anchor_stiffness_N_per_m.size() != model.num_particles) return;
  const bool jacobians = sink->wants_jacobians();
  for (int p = 0; p < model.num_particles; ++p) {
    const double k = state.anchor_stiffness_N_per_m[p];
    if (k == 0.0) continue;
    sink->AddForce(p, k * (state.anchor_W_m.segment<3>(3 * p) - state.x_W_m.segment<3>(3 * p)));
    if (jacobians) {
      // sink->AddDx(diag slot, p, p, -k I) on the diagonal only: the off-diagonal terms it
      // would add are zeros, which leave an accumulated (never -0) entry as it is. Likewise
      // (-k I) v's zero terms in dfdx_v, which also starts at +0 and only takes additions.
      double* b = (*sink->system)[static_cast<std::size_t>(model.pattern.diag_slot[static_cast<std::size_t>(p)])].data();
      const double d = sink->dx_scale * -k;
      b[0] += d;
      b[4] += d;
      b[8] += d;
      double* dfdx_v = sink->dfdx_v->data() + 3 * p;
      const double* v = sink->v->data() + 3 * p;
#pragma GCC unroll 3
      for (int i = 0; i < 3; ++i) dfdx_v[i] += -k * v[i];
    }
  }
}

double MaxAnchorStiffnessPerMass(const FabricModel& model, const FabricState& state) {
  if (state.anchor_stiffness_N_per_m.size() != model.num_particles) return 0.0;
  double m = 0.0;
  for (int p = 0; p < model.num_particles; ++p) {
    m = std::max(m, state.anchor_stiffness_N_per_m[p] / model.mass_kg[p]);
  }
  return m;
}

}  // namespace haptex::textile
