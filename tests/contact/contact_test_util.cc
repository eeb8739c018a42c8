#include "tests/contact/contact_test_util.h"

#include <algorithm>

#include "libs/textile/fabric_model.h"
#include "libs/textile/fabric_state.h"
#include "tests/textile/fabric_textproto.h"

namespace haptex::contact::testing {

textile::FabricMaterial DatabaseMaterial(const std::string& name) {
  return textile::MaterialFromKes(textile::testing::LoadDatabaseFabric(name));
}

std::unique_ptr<PatchSimulation> MakeFlatPatch(const textile::FabricMaterial& material, double size_m, int n,
                                               const ContactOptions& options, const textile::StepOptions& step,
                                               double pretension_strain) {
  textile::FabricModel model = textile::BuildFabricModel(material, {size_m, size_m, n, n});
  textile::Placement placement;
  placement.origin_W = Eigen::Vector3d(-0.5 * size_m, -0.5 * size_m, 0.0);
  textile::FabricState state = textile::MakeRestState(model, placement);
  state.x_W_m *= 1.0 + pretension_strain;
  for (int p : model.mesh.BorderParticles()) state.Fix(p);
  return std::make_unique<PatchSimulation>(std::move(model), std::move(state), step, options);
}

Eigen::Vector3d Ramp(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double t, double t0, double t1) {
  const double s = std::clamp((t - t0) / (t1 - t0), 0.0, 1.0);
  return a + s * (b - a);
}

textile::StepOptions LocalStep(double dt_s) {
  textile::StepOptions step;
  step.dt_s = dt_s;
  step.cg_tolerance = 1e-3;
  step.cg_max_iterations = 100;
  step.preconditioner = textile::Preconditioner::kBlockJacobi;
  return step;
}

}  // namespace haptex::contact::testing
