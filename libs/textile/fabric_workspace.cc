#include "libs/textile/fabric_workspace.h"

namespace haptex::textile {

FabricWorkspace::FabricWorkspace(const FabricModel& model, Preconditioner preconditioner)
    : multilevel(model),
      gauss_seidel(preconditioner == Preconditioner::kGaussSeidel ? GaussSeidelPreconditioner(model.product_rows)
                                                                  : GaussSeidelPreconditioner()) {
  const int n3 = 3 * model.num_particles;
  for (Eigen::VectorXd* v : {&force_N, &dfdx_v, &rhs, &dv, &dv0, &r, &c, &q, &s, &x_backup, &v_step_start,
                             &x_substep_start, &v_substep_start, &x_previous, &v_previous, &x_left, &v_left}) {
    *v = Eigen::VectorXd::Zero(n3);
  }
  system.assign(static_cast<std::size_t>(model.pattern.num_blocks()), Eigen::Matrix3d::Zero());
  system_base = system;
  system_scalars.assign(model.product_rows.scalar_slot.size(), 0.0);
  stiffness_row = Eigen::VectorXd::Zero(model.num_particles);
  if (preconditioner == Preconditioner::kGaussSeidel) {
    for (PaddedVector* v : {&split.r, &split.c, &split.q, &split.s, &split.t, &split.z, &split.y}) {
      *v = PaddedVector(model.num_particles);
    }
  }
  precond.assign(static_cast<std::size_t>(model.num_particles), Eigen::Matrix3d::Zero());
}

}  // namespace haptex::textile
