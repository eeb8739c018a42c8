#include "libs/textile/anchor_spring_force.h"

#include <algorithm>

namespace haptex::textile {

void AddAnchorSpringForces(const FabricModel& model, const FabricState& state, ForceSink* sink) {
  const int n = model.num_particles;
  if (state.anchor_stiffness_N_per_m.size() != n) return;
  const bool jacobians = sink->wants_jacobians();
  // Data in locals: the stores could alias the containers, so their pointers would be reloaded
  // every particle.
  const double* stiffness = state.anchor_stiffness_N_per_m.data();
  const double* anchor = state.anchor_W_m.data();
  const double* x = state.x_W_m.data();
  double* force = sink->force_N->data();
  const int* diag_slot = model.pattern.diag_slot.data();
  Eigen::Matrix3d* system = jacobians ? sink->system->data() : nullptr;
  double* dfdx_v = jacobians ? sink->dfdx_v->data() : nullptr;
  const double* v = jacobians ? sink->v->data() : nullptr;
  const double dx_scale = sink->dx_scale;
  for (int p = 0; p < n; ++p) {
    const double k = stiffness[p];
    if (k == 0.0) continue;
    // sink->AddForce(p, k (anchor_p - x_p)), component by component.
    double* f = force + 3 * p;
#pragma GCC unroll 3
    for (int i = 0; i < 3; ++i) f[i] += k * (anchor[3 * p + i] - x[3 * p + i]);
    if (jacobians) {
      // sink->AddDx(diag slot, p, p, -k I) on the diagonal only: the off-diagonal terms it
      // would add are zeros, which leave an accumulated (never -0) entry as it is. Likewise
      // (-k I) v's zero terms in dfdx_v, which also starts at +0 and only takes additions.
      double* b = system[diag_slot[p]].data();
      const double d = dx_scale * -k;
      b[0] += d;
      b[4] += d;
      b[8] += d;
#pragma GCC unroll 3
      for (int i = 0; i < 3; ++i) dfdx_v[3 * p + i] += -k * v[3 * p + i];
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
