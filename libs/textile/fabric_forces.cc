#include "libs/textile/fabric_forces.h"

#include "libs/textile/bending_force.h"
#include "libs/textile/drag_force.h"
#include "libs/textile/external_force.h"
#include "libs/textile/shear_force.h"
#include "libs/textile/tensile_force.h"

namespace haptex::textile {

void AccumulateForces(const FabricModel& model, const FabricState& state, ForceSink* sink) {
  const Eigen::VectorXd& x = state.x_W_m;
  const Eigen::VectorXd& v = state.v_W_m_per_s;
  AddTensileForces(model, x, v, sink);
  AddShearForces(model, x, v, sink);
  AddBendingForces(model, x, v, sink);
  AddDragForces(model, x, v, sink);
  AddExternalForces(model, state, sink);
}

}  // namespace haptex::textile
