#include "libs/textile/symplectic_euler.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "libs/textile/fabric_forces.h"

namespace haptex::textile {
namespace {

// Steepest slope of a curve over its data (sampled between knots) [N/m].
double SteepestSlope(const StrainCurve& curve) {
  double s = curve.compression_N_per_m();
  const auto& x = curve.loading().knots_x();
  for (std::size_t k = 0; k + 1 < x.size(); ++k) {
    for (int i = 0; i <= 8; ++i) {
      s = std::max(s, curve.loading().Slope(x[k] + (x[k + 1] - x[k]) * i / 8.0));
    }
  }
  return s;
}

}  // namespace

double EstimateExplicitStableStep(const FabricModel& model) {
  const double ku = SteepestSlope(model.material.tensile_warp);
  const double kv = SteepestSlope(model.material.tensile_weft);
  const double ks = SteepestSlope(model.material.shear);
  Eigen::VectorXd row = Eigen::VectorXd::Zero(model.num_particles);
  // Gershgorin: |d f_k/d x_l| summed over l, for stretch with tangent k and shear at rest.
  for (const auto& e : model.triangles) {
    for (std::size_t k = 0; k < 3; ++k) {
      double sum = 0.0;
      for (std::size_t l = 0; l < 3; ++l) {
        sum += std::abs(e.a[k] * e.a[l]) * ku + std::abs(e.b[k] * e.b[l]) * kv +
               (std::abs(e.a[k]) + std::abs(e.b[k])) * (std::abs(e.a[l]) + std::abs(e.b[l])) * ks;
      }
      row[e.p[k]] += e.area_m2 * sum;
    }
  }
  for (const auto& e : model.bends) {
    for (std::size_t k = 0; k < 3; ++k) {
      double sum = 0.0;
      for (std::size_t l = 0; l < 3; ++l) sum += std::abs(e.alpha[k] * e.alpha[l]);
      row[e.p[k]] += e.lambda_N_per_m * sum;
    }
  }
  double omega2 = 0.0;
  for (int p = 0; p < model.num_particles; ++p) omega2 = std::max(omega2, row[p] / model.mass_kg[p]);
  if (!(omega2 > 0.0)) return 1.0;
  const double omega = std::sqrt(omega2);
  const DampingOptions& d = model.options.damping;
  const double zeta = 0.5 * std::max({d.stretch_s, d.shear_s, d.bend_s}) * omega;
  return 0.9 * 2.0 / omega * (std::sqrt(1.0 + zeta * zeta) - zeta);
}

int SymplecticSubsteps(const FabricModel& model, const StepOptions& options) {
  ValidateStepOptions(options);
  const double stable = EstimateExplicitStableStep(model);
  const double needed_d = std::ceil(options.dt_s / stable);
  const int needed = needed_d > 1e9 ? 1000000000 : std::max(1, static_cast<int>(needed_d));
  if (needed > options.max_substeps) {
    std::ostringstream msg;
    msg << "StepOptions: symplectic Euler needs " << needed << " substeps for dt_s=" << options.dt_s
        << " (stable substep " << stable << " s), more than max_substeps=" << options.max_substeps
        << "; use implicit Euler or a smaller dt_s";
    throw std::invalid_argument(msg.str());
  }
  if (options.substeps == 0) return needed;
  if (options.substeps < needed) {
    std::ostringstream msg;
    msg << "StepOptions.substeps=" << options.substeps << " is unstable for this fabric and dt_s="
        << options.dt_s << "; needs >= " << needed << " (stable substep " << stable << " s)";
    throw std::invalid_argument(msg.str());
  }
  return options.substeps;
}

void SymplecticEulerStep(const FabricModel& model, const StepOptions& options, int substeps,
                         FabricState* state, FabricWorkspace* ws) {
  const double h = options.dt_s / substeps;
  ForceSink sink;
  sink.force_N = &ws->force_N;
  for (int s = 0; s < substeps; ++s) {
    ws->force_N.setZero();
    AccumulateForces(model, *state, &sink);
    for (int p = 0; p < model.num_particles; ++p) {
      if (state->mode[static_cast<std::size_t>(p)] == ParticleMode::kFree) {
        state->v_W_m_per_s.segment<3>(3 * p) += (h / model.mass_kg[p]) * ws->force_N.segment<3>(3 * p);
      } else {
        state->v_W_m_per_s.segment<3>(3 * p) = state->prescribed_v_W_m_per_s.segment<3>(3 * p);
      }
    }
    state->x_W_m += h * state->v_W_m_per_s;
  }
  state->time_s += options.dt_s;
}

}  // namespace haptex::textile
