#include "libs/textile/step_options.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace haptex::textile {

const char* IntegratorName(Integrator integrator) {
  switch (integrator) {
    case Integrator::kImplicitEuler:
      return "implicit_euler";
    case Integrator::kSymplecticEuler:
      return "symplectic_euler";
    case Integrator::kBdf2:
      return "bdf2";
  }
  return "unknown";
}

void ValidateStepOptions(const StepOptions& o) {
  auto fail = [](const std::string& what) { throw std::invalid_argument("StepOptions." + what); };
  if (!(std::isfinite(o.dt_s) && o.dt_s > 0.0)) fail("dt_s must be finite and > 0");
  if (!(o.cg_tolerance > 0.0 && o.cg_tolerance < 1.0)) fail("cg_tolerance must be in (0, 1)");
  if (o.cg_max_iterations < 1) fail("cg_max_iterations must be >= 1");
  if (o.substeps < 0) fail("substeps must be >= 0 (0 = automatic)");
  if (o.max_substeps < 1) fail("max_substeps must be >= 1");
  if (!(o.max_speed_m_per_s > 0.0)) fail("max_speed_m_per_s must be > 0");
  if (!(o.ssor_omega > 0.0 && o.ssor_omega < 2.0)) fail("ssor_omega must be in (0, 2)");
  if (o.newton_max_iterations < 1) fail("newton_max_iterations must be >= 1");
  if (!(o.newton_tolerance > 0.0 && o.newton_tolerance < 1.0)) fail("newton_tolerance must be in (0, 1)");
  if (o.max_step_halvings < 0 || o.max_step_halvings > kMaxStepHalvings) {
    fail("max_step_halvings must be in [0, " + std::to_string(kMaxStepHalvings) + "]");
  }
  if (!(o.max_strain_rise_per_step >= 0.0 && std::isfinite(o.max_strain_rise_per_step))) {
    fail("max_strain_rise_per_step must be finite and >= 0 (0 = no bound)");
  }
  if (o.method == Integrator::kBdf2 && o.newton_max_iterations < 2) {
    fail(
        "method kBdf2 needs newton_max_iterations >= 2 (one linearised step of it pumps energy into stiff or "
        "strongly nonlinear fabrics)");
  }
  if (o.method != Integrator::kImplicitEuler && o.method != Integrator::kSymplecticEuler &&
      o.method != Integrator::kBdf2) {
    fail("method is unknown");
  }
  if (o.preconditioner != Preconditioner::kBlockJacobi && o.preconditioner != Preconditioner::kMultilevel &&
      o.preconditioner != Preconditioner::kGaussSeidel) {
    fail("preconditioner is unknown");
  }
}

}  // namespace haptex::textile
