#include "libs/textile/symplectic_euler.h"

#include <algorithm>
#include <array>
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

namespace {

// Adds one tensile direction's block-Gershgorin row sums: |A w_k w_l| ||kx||, with
// kx = slope d d^T + t (I - d d^T) (eigenvalues slope and t, t = |sigma| / |d|).
void AddTensileRows(const TriangleElement& e, const std::array<double, 3>& w, const StrainCurve& curve,
                    const Eigen::Vector3d& d, Eigen::VectorXd* row) {
  const double len = d.norm();
  if (!(len > 1e-12)) return;
  double sigma = 0.0, slope = 0.0;
  curve.Evaluate(len - 1.0, &sigma, &slope);
  const double k = std::max(std::abs(slope), std::abs(sigma) / len);
  const double wsum = std::abs(w[0]) + std::abs(w[1]) + std::abs(w[2]);
  for (std::size_t i = 0; i < 3; ++i) (*row)[e.p[i]] += e.area_m2 * std::abs(w[i]) * wsum * k;
}

}  // namespace

double EstimateExplicitStableStep(const FabricModel& model, const FabricState& state, Eigen::VectorXd* row) {
  if (row->size() != model.num_particles) row->resize(model.num_particles);
  row->setZero();
  const Eigen::VectorXd& x = state.x_W_m;
  for (const auto& e : model.triangles) {
    Eigen::Vector3d u = Eigen::Vector3d::Zero(), w = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < 3; ++k) {
      u += e.a[k] * x.segment<3>(3 * e.p[k]);
      w += e.b[k] * x.segment<3>(3 * e.p[k]);
    }
    AddTensileRows(e, e.a, model.material.tensile_warp, u, row);
    AddTensileRows(e, e.b, model.material.tensile_weft, w, row);
    // Shear: A (slope g_k g_l^T + tau (a_k b_l + b_k a_l) I); ||g_k g_l^T|| = |g_k| |g_l|.
    double tau = 0.0, slope = 0.0;
    model.material.shear.Evaluate(u.dot(w), &tau, &slope);
    std::array<double, 3> g;  // |g_k|, g_k = a_k V + b_k U
    for (std::size_t k = 0; k < 3; ++k) g[k] = (e.a[k] * w + e.b[k] * u).norm();
    const double gsum = g[0] + g[1] + g[2];
    for (std::size_t k = 0; k < 3; ++k) {
      double geo = 0.0;
      for (std::size_t l = 0; l < 3; ++l) geo += std::abs(e.a[k] * e.b[l] + e.b[k] * e.a[l]);
      (*row)[e.p[k]] += e.area_m2 * (std::abs(slope) * g[k] * gsum + std::abs(tau) * geo);
    }
  }
  for (const auto& e : model.bends) {
    const double asum = std::abs(e.alpha[0]) + std::abs(e.alpha[1]) + std::abs(e.alpha[2]);
    for (std::size_t k = 0; k < 3; ++k) {
      (*row)[e.p[k]] += e.lambda_N_per_m * std::abs(e.alpha[k]) * asum;
    }
  }
  double omega2 = 0.0;
  for (int p = 0; p < model.num_particles; ++p) {
    if (state.mode[static_cast<std::size_t>(p)] != ParticleMode::kFree) continue;
    omega2 = std::max(omega2, (*row)[p] / model.mass_kg[p]);
  }
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
    msg << "StepOptions.substeps=" << options.substeps << " is unstable for this fabric and dt_s=" << options.dt_s
        << "; needs >= " << needed << " (stable substep " << stable << " s)";
    throw std::invalid_argument(msg.str());
  }
  return options.substeps;
}

void SymplecticEulerStep(const FabricModel& model, const StepOptions& options, int substeps, FabricState* state,
                         FabricWorkspace* ws) {
  const double h = options.dt_s / substeps;
  ForceSink sink;
  sink.force_N = &ws->force_N;
  for (int s = 0; s < substeps; ++s) {
    ws->force_N.setZero();
    AccumulateForces(model, *state, &sink);
    const bool anchors = state->anchor_stiffness_N_per_m.size() == model.num_particles;
    for (int p = 0; p < model.num_particles; ++p) {
      if (state->mode[static_cast<std::size_t>(p)] == ParticleMode::kFree) {
        auto v = state->v_W_m_per_s.segment<3>(3 * p);
        const double k = anchors ? state->anchor_stiffness_N_per_m[p] : 0.0;
        if (k == 0.0) {
          v += (h / model.mass_kg[p]) * ws->force_N.segment<3>(3 * p);
        } else {
          // The anchor spring is implicit per particle (stable for any k):
          // m (v' - v) = h (f + k (a - x - h v')).
          const double c = h * h * k / model.mass_kg[p];
          const Eigen::Vector3d spring = k * (state->anchor_W_m.segment<3>(3 * p) - state->x_W_m.segment<3>(3 * p));
          v = (v + (h / model.mass_kg[p]) * (ws->force_N.segment<3>(3 * p) + spring)) / (1.0 + c);
        }
      } else {
        state->v_W_m_per_s.segment<3>(3 * p) = state->prescribed_v_W_m_per_s.segment<3>(3 * p);
      }
    }
    state->x_W_m += h * state->v_W_m_per_s;
  }
  state->time_s += options.dt_s;
}

}  // namespace haptex::textile
