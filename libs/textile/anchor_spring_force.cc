#include "libs/textile/anchor_spring_force.h"

#include <algorithm>

namespace haptex::textile {

void AddAnchorSpringForces(const FabricModel& model, const FabricState& state, ForceSink* sink) {
  if (state.anchor_stiffness_N_per_m.size() != model.num_particles) return;
  for (int p = 0; p < model.num_particles; ++p) {
    const double k = state.anchor_stiffness_N_per_m[p];
    if (k == 0.0) continue;
    sink->AddForce(p, k * (state.anchor_W_m.segment<3>(3 * p) - state.x_W_m.segment<3>(3 * p)));
    if (sink->wants_jacobians()) {
      sink->AddDx(model.pattern.diag_slot[static_cast<std::size_t>(p)], p, p,
                  -k * Eigen::Matrix3d::Identity());
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
