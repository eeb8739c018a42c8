#include "libs/textile/implicit_euler.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include <Eigen/Dense>

#include "libs/base/demand.h"
#include "libs/textile/anchor_spring_force.h"
#include "libs/textile/fabric_forces.h"

namespace haptex::textile {
namespace {

bool IsFree(const FabricState& s, int p) { return s.mode[static_cast<std::size_t>(p)] == ParticleMode::kFree; }

// Components 0 and 1 of a particle as a pair (SSE2 in any x86-64 build), component 2 apart:
// the per-particle passes below do per component the operations Eigen did, in half the code.
using V2 = double __attribute__((vector_size(16)));
inline V2 Load2(const double* p) {
  V2 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
inline void Store2(double* p, V2 v) { std::memcpy(p, &v, sizeof v); }

// y = filter(A x), with A = ws->system (its bend-only blocks read as ws->system_scalars);
// returns x . y.
double FilteredMultiply(const FabricModel& model, const FabricState& state, const FabricWorkspace& ws,
                        const Eigen::VectorXd& x, Eigen::VectorXd* y) {
  const ParticleMode* mode = state.mode.data();
  return MultiplySplitRows(
      model.product_rows, ws.system, ws.system_scalars, [mode](int r) { return mode[r] == ParticleMode::kFree; }, x, y);
}

// y = P^-1 x for free particles, 0 for constrained ones.
void Precondition(const FabricModel& model, const FabricState& state, const StepOptions& options, FabricWorkspace* ws,
                  const Eigen::VectorXd& x, Eigen::VectorXd* y) {
  if (options.preconditioner == Preconditioner::kMultilevel) {
    ws->multilevel.Apply(x, y);
    return;
  }
  const std::vector<Eigen::Matrix3d>& p_inv = ws->precond;
  for (int r = 0; r < model.num_particles; ++r) {
    if (IsFree(state, r)) {
      y->segment<3>(3 * r).noalias() = p_inv[static_cast<std::size_t>(r)] * x.segment<3>(3 * r);
    } else {
      y->segment<3>(3 * r).setZero();
    }
  }
}

// A step's accumulators before the forces are added: force_N = 0, dfdx_v = 0, and system =
// system_base where the forces do not start from it themselves (the triangle kernel's first
// addition to a block reads system_base: the sink's; the scalar blocks never change). Only the
// general blocks no triangle touches are copied.
void ResetStep(const FabricModel& model, FabricWorkspace* ws, ForceSink* sink) {
  ws->force_N.setZero();
  ws->dfdx_v.setZero();
  for (int slot : model.general_slots_without_triangles) {
    ws->system[static_cast<std::size_t>(slot)] = ws->system_base[static_cast<std::size_t>(slot)];
  }
  sink->system_base = ws->system_base.data();
}

// The constant part of the system (mass, bending, linear drag) for step h (the sink's scales)
// into ws->system_base and the values of its scalar blocks; `sink` is the step's, aimed at
// ws->system again on return.
void BuildSystemBase(const FabricModel& model, double h, ForceSink* sink, FabricWorkspace* ws) {
  const int n = model.num_particles;
  for (auto& b : ws->system_base) b.setZero();
  for (int p = 0; p < n; ++p) {
    const int slot = model.pattern.diag_slot[static_cast<std::size_t>(p)];
    ws->system_base[static_cast<std::size_t>(slot)] += model.mass_kg[p] * Eigen::Matrix3d::Identity();
  }
  sink->system = &ws->system_base;
  AddConstantJacobians(model, sink);
  sink->system = &ws->system;
  const SplitRows& split = model.product_rows;
  for (std::size_t k = 0; k < split.scalar_slot.size(); ++k) {
    const Eigen::Matrix3d& b = ws->system_base[static_cast<std::size_t>(split.scalar_slot[k])];
    HAPTEX_DEMAND(b == b(0, 0) * Eigen::Matrix3d::Identity());  // bending only
    ws->system_scalars[k] = b(0, 0);
  }
  ws->system_base_model = &model;
  ws->system_base_dt_s = h;
  ws->system = ws->system_base;
}

// Block-Jacobi preconditioner: the inverted diagonal blocks of the system.
void UpdateBlockJacobi(const FabricModel& model, FabricWorkspace* ws) {
  for (int p = 0; p < model.num_particles; ++p) {
    ws->precond[static_cast<std::size_t>(p)] =
        ws->system[static_cast<std::size_t>(model.pattern.diag_slot[static_cast<std::size_t>(p)])].inverse();
  }
}

// CG's entry, from the reference size delta0 and |filtered rhs|^2: non-finite sizes end the
// solve (report->finite false), a zero right-hand side gives the exact dv = 0 on the free
// particles, a non-positive reference is a breakdown.
enum class PcgStart { kIterate, kDone, kBreakdown };
PcgStart StartPcg(const FabricModel& model, const FabricState& state, double delta0, double rhs_norm2, bool finite,
                  FabricWorkspace* ws, CgReport* report) {
  report->iterations = 0;
  report->relative_residual = 0.0;
  report->converged = true;
  report->finite = finite && std::isfinite(delta0) && std::isfinite(rhs_norm2);
  if (!report->finite) return PcgStart::kDone;
  if (rhs_norm2 == 0.0) {
    for (int p = 0; p < model.num_particles; ++p) {
      if (IsFree(state, p)) ws->dv.segment<3>(3 * p).setZero();
    }
    return PcgStart::kDone;
  }
  return delta0 > 0.0 ? PcgStart::kIterate : PcgStart::kBreakdown;
}

// CG's vectors: the residual, direction, product and preconditioned residual.
struct CgVectors {
  Eigen::VectorXd* r;
  Eigen::VectorXd* c;
  Eigen::VectorXd* q;
  Eigen::VectorXd* s;
};

// CG's report after `it` iterations ending at delta (the preconditioned residual norm squared).
// Iterate and RunGaussSeidelPcg's fused copy of its loop both end here.
void FinishReport(double delta, double delta0, double eps2, int it, bool breakdown, CgReport* report) {
  report->iterations = it;
  report->relative_residual = std::sqrt(std::max(delta, 0.0) / delta0);
  report->converged = !breakdown && delta <= eps2 * delta0;
  report->finite = std::isfinite(delta);
}

// The PCG iterations from the residual in v.r, with product(c, &q) = A c returning c'Ac,
// precondition(r, &s) = P^-1 r returning r's, and advance(alpha) moving the unknown by alpha
// along the direction (x += alpha c). Stops at the tolerance relative to delta0 or at the
// iteration cap; fills the report. Returns true on a breakdown (a non-positive c'Ac or r'P^-1 r).
// RunGaussSeidelPcg has this loop with its passes fused: a change here belongs there too.
template <typename ProductFn, typename PreconditionFn, typename AdvanceFn>
bool Iterate(ProductFn product, PreconditionFn precondition, AdvanceFn advance, double delta0,
             const StepOptions& options, const CgVectors& v, CgReport* report) {
  double delta = precondition(*v.r, v.c);
  const double eps2 = options.cg_tolerance * options.cg_tolerance;
  bool breakdown = !(delta >= 0.0);
  int it = 0;
  while (!breakdown && delta > eps2 * delta0 && it < options.cg_max_iterations) {
    const double cq = product(*v.c, v.q);
    if (!(cq > 0.0)) {
      breakdown = true;
      break;
    }
    const double alpha = delta / cq;
    advance(alpha);
    *v.r -= alpha * *v.q;
    const double delta_old = delta;
    delta = precondition(*v.r, v.s);
    ++it;
    if (!(delta >= 0.0)) {
      breakdown = true;
      break;
    }
    *v.c = *v.s + (delta / delta_old) * *v.c;
  }
  FinishReport(delta, delta0, eps2, it, breakdown, report);
  return breakdown;
}

// Filtered PCG from the guess in ws->dv (Baraff-Witkin's modified PCG). Returns true on a
// breakdown (an indefinite preconditioner or matrix), leaving the best iterate in ws->dv.
bool RunPcg(const FabricModel& model, const FabricState& state, const StepOptions& options, Preconditioner pc,
            FabricWorkspace* ws, CgReport* report) {
  const int n = model.num_particles;
  StepOptions o = options;
  o.preconditioner = pc;
  // Reference size: the preconditioned norm of the filtered right-hand side.
  Precondition(model, state, o, ws, ws->rhs, &ws->s);
  double delta0 = 0.0, rhs_norm2 = 0.0;
  for (int p = 0; p < n; ++p) {
    if (!IsFree(state, p)) continue;
    delta0 += ws->rhs.segment<3>(3 * p).dot(ws->s.segment<3>(3 * p));
    rhs_norm2 += ws->rhs.segment<3>(3 * p).squaredNorm();
  }
  const PcgStart start = StartPcg(model, state, delta0, rhs_norm2, true, ws, report);
  if (start != PcgStart::kIterate) return start == PcgStart::kBreakdown;
  FilteredMultiply(model, state, *ws, ws->dv, &ws->q);
  for (int p = 0; p < n; ++p) {
    if (IsFree(state, p)) {
      ws->r.segment<3>(3 * p) = ws->rhs.segment<3>(3 * p) - ws->q.segment<3>(3 * p);
    } else {
      ws->r.segment<3>(3 * p).setZero();
    }
  }
  return Iterate(
      [&](const Eigen::VectorXd& c, Eigen::VectorXd* q) { return FilteredMultiply(model, state, *ws, c, q); },
      [&](const Eigen::VectorXd& r, Eigen::VectorXd* z) {
        Precondition(model, state, o, ws, r, z);
        return r.dot(*z);
      },
      [&](double alpha) { ws->dv += alpha * ws->c; }, delta0, options, CgVectors{&ws->r, &ws->c, &ws->q, &ws->s},
      report);
}

// rhs = h (f + h df/dx v), all rows.
void ComputeRhs(double h, FabricWorkspace* ws) { ws->rhs = h * (ws->force_N + h * ws->dfdx_v); }

// PCG on Gauss-Seidel's split system (gauss_seidel_preconditioner.h) for the correction to the
// guess in ws->dv: A y = r0 = filter(rhs - A dv), y~ = (D_w + U) y from 0, then dv += y. The
// tolerance is on r' M^-1 r relative to rhs' M^-1 rhs (M: the SSOR preconditioner), as RunPcg
// measures in its preconditioner's norm. The split system's vectors are padded (ws->split).
// Leaves ws->rhs stale (only the fallback's RunPcg reads it: ComputeRhs). Returns true on a
// breakdown (dv left at the guess); sets *add_y when the caller is to finish with dv += y
// (ws->split.y).
bool RunGaussSeidelPcg(const FabricModel& model, const FabricState& state, const StepOptions& options,
                       FabricWorkspace* ws, CgReport* report, bool* add_y) {
  *add_y = false;
  const int n = model.num_particles;
  const double h = options.dt_s;
  const GaussSeidelPreconditioner& gs = ws->gauss_seidel;
  const std::vector<Eigen::Matrix3d>& a = ws->system;
  const std::vector<double>& scalars = ws->system_scalars;
  FabricWorkspace::SplitVectors& v = ws->split;
  // s = filter(rhs); q = filter(rhs - A dv), padded; in one pass. q_zero stays 0 while q is
  // finite (0 x inf is NaN): its finiteness check.
  FilteredMultiply(model, state, *ws, ws->dv, &ws->q);
  // Component by component the operations of h (f + h dfdx_v), rhs - A dv, |rhs|^2 as
  // (x^2 + y^2) + z^2.
  double rhs_norm2 = 0.0;
  V2 q_zero01 = {0.0, 0.0};
  double q_zero2 = 0.0;
  const ParticleMode* mode = state.mode.data();
  const double* force = ws->force_N.data();
  const double* dfdx_v = ws->dfdx_v.data();
  const double* a_dv = ws->q.data();
  double* s_rows = v.s.data();
  double* q_rows = v.q.data();
  const V2 zero = {0.0, 0.0};
  for (int p = 0; p < n; ++p) {
    const double* f = force + 3 * p;
    const double* d = dfdx_v + 3 * p;
    const V2 rhs01 = h * (Load2(f) + h * Load2(d));
    const double rhs2 = h * (f[2] + h * d[2]);
    double* s_row = s_rows + 4 * p;
    double* q_row = q_rows + 4 * p;
    if (mode[p] == ParticleMode::kFree) {
      const V2 q01 = rhs01 - Load2(a_dv + 3 * p);
      const double q2 = rhs2 - a_dv[3 * p + 2];
      Store2(s_row, rhs01);
      Store2(s_row + 2, V2{rhs2, 0.0});
      Store2(q_row, q01);
      Store2(q_row + 2, V2{q2, 0.0});
      q_zero01 += 0.0 * q01;
      q_zero2 += 0.0 * q2;
      const V2 sq = rhs01 * rhs01;
      rhs_norm2 += (sq[0] + sq[1]) + rhs2 * rhs2;
    } else {
      Store2(s_row, zero);
      Store2(s_row + 2, zero);
      Store2(q_row, zero);
      Store2(q_row + 2, zero);
    }
  }
  const bool q_finite = std::isfinite(q_zero01[0]) && std::isfinite(q_zero01[1]) && std::isfinite(q_zero2);
  // In one pass: the reference size delta0 = s' M^-1 s (through z, t: scratch here), and
  // r~ = (D_w + L)^-1 r0 with the first direction c = D_w r~, delta = r~'c. Only delta0 when CG
  // cannot iterate (a zero or non-finite right-hand side: StartPcg ends there), as at rest.
  double sizes[2] = {0.0, 0.0};
  if (q_finite && std::isfinite(rhs_norm2) && rhs_norm2 != 0.0) {
    gs.ForwardSolveDiagonalPair(a, scalars, v.s, &v.z, &v.t, v.q, &v.r, &v.c, sizes);
  } else {
    sizes[0] = gs.ForwardSolveDiagonal(a, scalars, v.s, &v.z, &v.t);
  }
  const double delta0 = sizes[0];
  const PcgStart start = StartPcg(model, state, delta0, rhs_norm2, q_finite, ws, report);
  if (start != PcgStart::kIterate) return start == PcgStart::kBreakdown;
  double delta = sizes[1];
  // CG runs on y~ = (D_w + U) y from 0 (y = 0 until the first step), but y itself is kept: y = sum alpha_k (D_w + U)^-1
  // c_k, and the product leaves (D_w + U)^-1 c_k in t. That saves the backward sweep y~ -> y. Iterate's loop with its
  // passes fused: the direction update c = s + beta c is done by the next product, the unknown's and residual's updates
  // with the preconditioner.
  const double eps2 = options.cg_tolerance * options.cg_tolerance;
  bool breakdown = !(delta >= 0.0);
  double beta = 0.0;
  int it = 0;
  while (!breakdown && delta > eps2 * delta0 && it < options.cg_max_iterations) {
    const double cq = it == 0 ? gs.MultiplySplit(a, scalars, v.c, &v.t, &v.z, &v.q)
                              : gs.UpdateMultiplySplit(a, scalars, v.s, beta, &v.c, &v.t, &v.z, &v.q);
    if (!(cq > 0.0)) {
      breakdown = true;
      break;
    }
    const double alpha = delta / cq;
    const double delta_old = delta;
    delta = gs.StepResidual(alpha, v.t, v.q, it == 0, &v.y, &v.r, &v.s);
    ++it;
    if (!(delta >= 0.0)) {
      breakdown = true;
      break;
    }
    beta = delta / delta_old;
  }
  FinishReport(delta, delta0, eps2, it, breakdown, report);
  if (!breakdown && it == 0) v.y.SetZero();  // dv += 0 as well (-0 turns +0)
  *add_y = !breakdown;
  return breakdown;
}

// Forces at the state into ws->force_N and, with `jacobians`, the system A = M - h df/dv -
// h^2 df/dx with (df/dx) v into ws->dfdx_v, starting from the constant part built once per
// model and step.
void Assemble(const FabricModel& model, double h, const FabricState& state, bool jacobians, FabricWorkspace* ws) {
  ForceSink sink;
  sink.force_N = &ws->force_N;
  if (!jacobians) {
    ws->force_N.setZero();
    AccumulateForces(model, state, &sink);
    AddAnchorSpringForces(model, state, &sink);
    return;
  }
  sink.system = &ws->system;
  sink.dx_scale = -h * h;
  sink.dv_scale = -h;
  sink.dfdx_v = &ws->dfdx_v;
  sink.v = &state.v_W_m_per_s;
  if (ws->system_base_model != &model || ws->system_base_dt_s != h) BuildSystemBase(model, h, &sink, ws);
  ResetStep(model, ws, &sink);
  sink.constant_jacobians_added = true;
  AccumulateForces(model, state, &sink);
  AddAnchorSpringForces(model, state, &sink);
}

// The configured preconditioner for the current system; false when Gauss-Seidel's breaks down.
bool UpdatePreconditioner(const FabricModel& model, const StepOptions& options, const FabricState& state,
                          FabricWorkspace* ws) {
  const ParticleMode* mode = state.mode.data();
  if (options.preconditioner == Preconditioner::kMultilevel) {
    ws->multilevel.Update(model, state, ws->system);
  } else if (options.preconditioner == Preconditioner::kGaussSeidel) {
    HAPTEX_DEMAND(ws->gauss_seidel.rows() == model.num_particles);  // a workspace built for it
    return ws->gauss_seidel.Update(ws->system, options.ssor_omega,
                                   [mode](int r) { return mode[r] == ParticleMode::kFree; });
  } else {
    UpdateBlockJacobi(model, ws);
  }
  return true;
}

// Solves A dv = h (f + h dfdx_v) on the free particles from the guess in ws->dv (constrained
// rows keep the guess): modified PCG, on a preconditioner breakdown again from the same guess
// with block Jacobi. A non-finite dv is zeroed (never warm-start from garbage) and reported.
CgReport Solve(const FabricModel& model, const StepOptions& options, const FabricState& state, bool gauss_seidel_ok,
               FabricWorkspace* ws) {
  const int n = model.num_particles;
  const double h = options.dt_s;
  // Gauss-Seidel's PCG leaves dv at the guess on a breakdown; the others need a copy.
  const bool gs = options.preconditioner == Preconditioner::kGaussSeidel;
  if (!gs) {
    ComputeRhs(h, ws);
    ws->dv0 = ws->dv;
  }
  CgReport report;
  Preconditioner pc = options.preconditioner;
  bool add_y = false;
  bool breakdown = gs ? (!gauss_seidel_ok || RunGaussSeidelPcg(model, state, options, ws, &report, &add_y))
                      : RunPcg(model, state, options, pc, ws, &report);
  if (breakdown && pc != Preconditioner::kBlockJacobi) {
    report.preconditioner_fallback = true;
    if (gs) {
      ComputeRhs(h, ws);
    } else {
      ws->dv = ws->dv0;
    }
    pc = Preconditioner::kBlockJacobi;
    UpdateBlockJacobi(model, ws);
    breakdown = RunPcg(model, state, options, pc, ws, &report);
  }
  if (breakdown) report.converged = false;

  // dv's finiteness (dv_zero stays 0 while dv is finite), with Gauss-Seidel's dv += y; these
  // last passes per component as the right-hand side's.
  V2 dv_zero01 = {0.0, 0.0};
  double dv_zero2 = 0.0;
  double* dv = ws->dv.data();
  if (report.finite) {
    const double* y = ws->split.y.data();
    for (int p = 0; p < n; ++p) {
      double* d = dv + 3 * p;
      V2 d01 = Load2(d);
      double d2 = d[2];
      if (add_y) {
        d01 += Load2(y + 4 * p);
        d2 += y[4 * p + 2];
        Store2(d, d01);
        d[2] = d2;
      }
      dv_zero01 += 0.0 * d01;
      dv_zero2 += 0.0 * d2;
    }
  }
  report.finite =
      report.finite && std::isfinite(dv_zero01[0]) && std::isfinite(dv_zero01[1]) && std::isfinite(dv_zero2);
  if (!report.finite) ws->dv.setZero();
  return report;
}

// v += dv, then x += h v (`whole`: the step's first update) or x += h dv (a Newton correction);
// records the new state's finiteness and largest speed for the stepper's checks.
void Update(double h, bool whole, const Eigen::VectorXd& dv_all, FabricState* state, FabricWorkspace* ws) {
  V2 state_zero01 = {0.0, 0.0};
  double state_zero2 = 0.0;
  double max_speed2 = 0.0;
  double* v_all = state->v_W_m_per_s.data();
  double* x_all = state->x_W_m.data();
  const double* dv = dv_all.data();
  const int n = state->num_particles();
  for (int p = 0; p < n; ++p) {
    double* v = v_all + 3 * p;
    double* x = x_all + 3 * p;
    const double* d = dv + 3 * p;
    const V2 v01 = Load2(v) + Load2(d);
    const double v2 = v[2] + d[2];
    const V2 x01 = Load2(x) + h * (whole ? v01 : Load2(d));
    const double x2 = x[2] + h * (whole ? v2 : d[2]);
    Store2(v, v01);
    v[2] = v2;
    Store2(x, x01);
    x[2] = x2;
    state_zero01 += 0.0 * x01 + 0.0 * v01;
    state_zero2 += 0.0 * x2 + 0.0 * v2;
    const V2 sq = v01 * v01;
    max_speed2 = std::max(max_speed2, (sq[0] + sq[1]) + v2 * v2);
  }
  ws->stepped_state_finite =
      std::isfinite(state_zero01[0]) && std::isfinite(state_zero01[1]) && std::isfinite(state_zero2);
  ws->stepped_max_speed2_m2_per_s2 = max_speed2;
}

// |h (f + h dfdx_v)| over the free particles: the size of the step's first right-hand side.
double RhsNorm(const FabricState& state, double h, const FabricWorkspace& ws) {
  double sum2 = 0.0;
  for (int p = 0; p < state.num_particles(); ++p) {
    if (IsFree(state, p)) sum2 += (h * (ws.force_N.segment<3>(3 * p) + h * ws.dfdx_v.segment<3>(3 * p))).squaredNorm();
  }
  return std::sqrt(sum2);
}

// |h M g| over the free particles: the force level of a cloth at rest; without gravity, that of
// 1e-6 m/s^2, so a cloth at rest without loads meets the tolerance (round-off, not a zero target).
double WeightImpulseNorm(const FabricModel& model, const FabricState& state, double h) {
  constexpr double kLeastAcceleration_m_per_s2 = 1e-6;
  double sum2 = 0.0;
  for (int p = 0; p < model.num_particles; ++p) {
    if (IsFree(state, p)) sum2 += model.mass_kg[p] * model.mass_kg[p];
  }
  return h * std::max(model.options.gravity_m_per_s2.norm(), kLeastAcceleration_m_per_s2) * std::sqrt(sum2);
}

// The Newton residual g = h f(x, v) - M (v - v0) on the free particles, written so the
// right-hand side h (f + h dfdx_v) the solvers read is g: dfdx_v = -M (v - v0) / h^2 (a
// constrained row's value is never read). Returns |g|.
double NewtonResidual(const FabricModel& model, const FabricState& state, double h, FabricWorkspace* ws) {
  double sum2 = 0.0;
  const double inv_h2 = 1.0 / (h * h);
  for (int p = 0; p < model.num_particles; ++p) {
    const auto dv = state.v_W_m_per_s.segment<3>(3 * p) - ws->v_step_start.segment<3>(3 * p);
    ws->dfdx_v.segment<3>(3 * p) = -model.mass_kg[p] * inv_h2 * dv;
    if (IsFree(state, p)) sum2 += (h * ws->force_N.segment<3>(3 * p) - model.mass_kg[p] * dv).squaredNorm();
  }
  return std::sqrt(sum2);
}

// CG's relative tolerance for a right-hand side of size rhs_norm when the step's residual is to
// end below target: no tighter than the target needs (half of it, the rest left to the
// linearisation), never looser than configured, never below round-off.
double CgToleranceFor(const StepOptions& options, double target, double rhs_norm) {
  constexpr double kTightest = 1e-10;
  if (!(rhs_norm > 0.0)) return options.cg_tolerance;
  return std::clamp(0.5 * target / rhs_norm, kTightest, options.cg_tolerance);
}

}  // namespace

ImplicitStepReport ImplicitEulerStep(const FabricModel& model, const StepOptions& options, FabricState* state,
                                     FabricWorkspace* ws) {
  const double h = options.dt_s;
  const int n = model.num_particles;
  ws->stepped_state_finite = false;  // until a step has written the state
  ImplicitStepReport report;

  // Baraff-Witkin's step: the forces linearised at the step's start.
  Assemble(model, h, *state, true, ws);

  // Initial guess carries the prescribed velocity change (z). Data in locals: the stores to dv
  // could alias the containers, so their pointers would be reloaded every particle.
  const ParticleMode* mode = state->mode.data();
  {
    double* guess = ws->dv.data();
    const double* prescribed = state->prescribed_v_W_m_per_s.data();
    const double* v = state->v_W_m_per_s.data();
    const bool zero_free = !options.cg_warm_start;
    for (int p = 0; p < n; ++p) {
      double* d = guess + 3 * p;
      if (mode[p] == ParticleMode::kFree) {
        // Warm start: the previous step's velocity change is a good guess for a smooth motion.
        if (zero_free) {
          Store2(d, V2{0.0, 0.0});
          d[2] = 0.0;
        }
      } else {
        Store2(d, Load2(prescribed + 3 * p) - Load2(v + 3 * p));
        d[2] = prescribed[3 * p + 2] - v[3 * p + 2];
      }
    }
  }

  bool gauss_seidel_ok = UpdatePreconditioner(model, options, *state, ws);
  const bool newton = options.newton_max_iterations > 1;
  StepOptions solve_options = options;
  double target = 0.0;
  if (newton) {
    const double rhs_norm = RhsNorm(*state, h, *ws);
    target = options.newton_tolerance * std::max(rhs_norm, WeightImpulseNorm(model, *state, h));
    solve_options.cg_tolerance = CgToleranceFor(options, target, rhs_norm);
    ws->v_step_start = state->v_W_m_per_s;
  }
  report.cg = Solve(model, solve_options, *state, gauss_seidel_ok, ws);
  report.newton_iterations = 1;
  if (!report.cg.finite) return report;
  Update(h, true, ws->dv, state, ws);

  // Newton's further iterations on g(v1) = h f(x0 + h v1, v1) - M (v1 - v0) = 0, each from the
  // residual at the latest iterate; the warm start keeps the whole step's velocity change.
  // A correction that raised the residual is halved (backtracking, up to kMaxBacktracks times):
  // the Jacobian omits terms (docs/fabric-model.md) and the laws' slopes change at zero strain,
  // so a full correction can overshoot.
  constexpr int kMaxBacktracks = 3;
  double previous_residual = std::numeric_limits<double>::infinity();
  int backtracks = 0;
  for (int k = 1; newton && ws->stepped_state_finite;) {
    Assemble(model, h, *state, options.newton_update_jacobian, ws);
    const double residual = NewtonResidual(model, *state, h, ws);
    report.newton_relative_residual = target > 0.0 ? residual / (target / options.newton_tolerance) : 0.0;
    if (residual <= target) break;
    if (!(residual < previous_residual) && backtracks < kMaxBacktracks) {
      ws->dv *= -0.5;  // back to half the last correction
      Update(h, false, ws->dv, state, ws);
      ws->dv *= -1.0;
      ++backtracks;
      continue;
    }
    if (!std::isfinite(residual) || k == options.newton_max_iterations) {
      report.newton_converged = false;
      break;
    }
    previous_residual = residual;
    backtracks = 0;
    if (options.newton_update_jacobian) gauss_seidel_ok = UpdatePreconditioner(model, options, *state, ws);
    ws->dv.setZero();
    solve_options.cg_tolerance = CgToleranceFor(options, target, residual);
    const CgReport correction = Solve(model, solve_options, *state, gauss_seidel_ok, ws);
    report.cg.iterations += correction.iterations;
    report.cg.relative_residual = correction.relative_residual;
    report.cg.converged = report.cg.converged && correction.converged;
    report.cg.preconditioner_fallback = report.cg.preconditioner_fallback || correction.preconditioner_fallback;
    report.cg.finite = correction.finite;
    ++report.newton_iterations;
    ++k;
    if (!correction.finite) return report;
    Update(h, false, ws->dv, state, ws);
  }
  if (newton) ws->dv = state->v_W_m_per_s - ws->v_step_start;
  state->time_s += h;
  return report;
}

}  // namespace haptex::textile
