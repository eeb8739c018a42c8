#include "libs/textile/implicit_euler.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "libs/textile/anchor_spring_force.h"
#include "libs/textile/check.h"
#include "libs/textile/fabric_forces.h"

namespace haptex::textile {
namespace {

bool IsFree(const FabricState& s, int p) {
  return s.mode[static_cast<std::size_t>(p)] == ParticleMode::kFree;
}

// y = filter(A x), with A = ws->system (its bend-only blocks read as ws->system_scalars);
// returns x . y.
double FilteredMultiply(const FabricModel& model, const FabricState& state,
                        const FabricWorkspace& ws, const Eigen::VectorXd& x, Eigen::VectorXd* y) {
  const ParticleMode* mode = state.mode.data();
  return MultiplySplitRows(model.product_rows, ws.system, ws.system_scalars,
                    [mode](int r) { return mode[r] == ParticleMode::kFree; }, x, y);
}

// y = P^-1 x for free particles, 0 for constrained ones.
void Precondition(const FabricModel& model, const FabricState& state, const StepOptions& options,
                  FabricWorkspace* ws, const Eigen::VectorXd& x, Eigen::VectorXd* y) {
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

// f(slot) for each general block of row r (contiguous slots).
template <typename Fn>
void ForEachGeneralSlot(const SplitRows& split, int r, Fn f) {
  const auto row = static_cast<std::size_t>(r);
  const int first = split.general_first_slot[row];
  const int count = split.general_start[row + 1] - split.general_start[row];
  for (int k = 0; k < count; ++k) f(static_cast<std::size_t>(first + k));
}

// system = system_base before the state-dependent blocks are added: only the general blocks,
// from their scalars, where the workspace has them (the scalar blocks never change).
void ResetSystem(const SplitRows& split, int n, FabricWorkspace* ws) {
  if (ws->system_base_general_scalars.empty()) {
    ws->system = ws->system_base;
    return;
  }
  const double* scalars = ws->system_base_general_scalars.data();
  Eigen::Matrix3d* system = ws->system.data();
  for (int r = 0; r < n; ++r) {
    ForEachGeneralSlot(split, r, [&](std::size_t slot) {
      double* b = system[slot].data();
      const double d = scalars[slot];
      b[0] = d, b[1] = 0.0, b[2] = 0.0, b[3] = 0.0, b[4] = d, b[5] = 0.0, b[6] = 0.0, b[7] = 0.0, b[8] = d;
    });
  }
}

// The constant part of the system (mass, bending, linear drag) for step h (the sink's scales)
// into ws->system_base, the values of its scalar blocks, and what ResetSystem needs; `sink` is
// the step's, aimed at ws->system again on return.
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
    HAPTEX_TEXTILE_DEMAND(b == b(0, 0) * Eigen::Matrix3d::Identity());  // bending only
    ws->system_scalars[k] = b(0, 0);
  }
  ws->system_base_model = &model;
  ws->system_base_dt_s = h;
  ws->system = ws->system_base;
  ws->system_base_general_scalars.assign(ws->system_base.size(), 0.0);
  bool all_scalar = true;
  for (int r = 0; r < n; ++r) {
    ForEachGeneralSlot(split, r, [&](std::size_t slot) {
      const Eigen::Matrix3d& b = ws->system_base[slot];
      all_scalar = all_scalar && b == b(0, 0) * Eigen::Matrix3d::Identity();
      ws->system_base_general_scalars[slot] = b(0, 0);
    });
  }
  if (!all_scalar) ws->system_base_general_scalars.clear();  // steps copy whole blocks
}

// Block-Jacobi preconditioner: the inverted diagonal blocks of the system.
void UpdateBlockJacobi(const FabricModel& model, FabricWorkspace* ws) {
  for (int p = 0; p < model.num_particles; ++p) {
    ws->precond[static_cast<std::size_t>(p)] =
        ws->system[static_cast<std::size_t>(model.pattern.diag_slot[static_cast<std::size_t>(p)])]
            .inverse();
  }
}

// CG's entry, from the reference size delta0 and |filtered rhs|^2: non-finite sizes end the
// solve (report->finite false), a zero right-hand side gives the exact dv = 0 on the free
// particles, a non-positive reference is a breakdown.
enum class PcgStart { kIterate, kDone, kBreakdown };
PcgStart StartPcg(const FabricModel& model, const FabricState& state, double delta0,
                  double rhs_norm2, bool finite, FabricWorkspace* ws, CgReport* report) {
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

// An Eigen view of a CG vector: itself, or a padded vector's entries (pads stay 0).
Eigen::VectorXd& View(Eigen::VectorXd& v) { return v; }
Eigen::Map<Eigen::VectorXd, Eigen::Aligned32> View(PaddedVector& v) { return v.vec(); }

// CG's vectors: the residual, direction, product and preconditioned residual.
template <typename Vector>
struct CgVectors {
  Vector* r;
  Vector* c;
  Vector* q;
  Vector* s;
};

// The PCG iterations from the residual in v.r, with product(c, &q) = A c returning c'Ac,
// precondition(r, &s) = P^-1 r returning r's, and advance(alpha) moving the unknown by alpha
// along the direction (x += alpha c). Stops at the tolerance relative to delta0 or at the
// iteration cap; fills the report. Returns true on a breakdown (a non-positive c'Ac or r'P^-1 r).
template <typename Vector, typename ProductFn, typename PreconditionFn, typename AdvanceFn>
bool Iterate(ProductFn product, PreconditionFn precondition, AdvanceFn advance, double delta0,
             const StepOptions& options, const CgVectors<Vector>& v, CgReport* report) {
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
    View(*v.r) -= alpha * View(*v.q);
    const double delta_old = delta;
    delta = precondition(*v.r, v.s);
    ++it;
    if (!(delta >= 0.0)) {
      breakdown = true;
      break;
    }
    View(*v.c) = View(*v.s) + (delta / delta_old) * View(*v.c);
  }
  report->iterations = it;
  report->relative_residual = std::sqrt(std::max(delta, 0.0) / delta0);
  report->converged = !breakdown && delta <= eps2 * delta0;
  report->finite = std::isfinite(delta);
  return breakdown;
}

// Filtered PCG from the guess in ws->dv (Baraff-Witkin's modified PCG). Returns true on a
// breakdown (an indefinite preconditioner or matrix), leaving the best iterate in ws->dv.
bool RunPcg(const FabricModel& model, const FabricState& state, const StepOptions& options,
            Preconditioner pc, FabricWorkspace* ws, CgReport* report) {
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
      [&](double alpha) { ws->dv += alpha * ws->c; }, delta0, options,
      CgVectors<Eigen::VectorXd>{&ws->r, &ws->c, &ws->q, &ws->s}, report);
}

// PCG on Gauss-Seidel's split system (gauss_seidel_preconditioner.h) for the correction to the
// guess in ws->dv: A y = r0 = filter(rhs - A dv), y~ = (D_w + U) y from 0, then dv += y. The
// tolerance is on r' M^-1 r relative to rhs' M^-1 rhs (M: the SSOR preconditioner), as RunPcg
// measures in its preconditioner's norm. The split system's vectors are padded (ws->split).
// Returns true on a breakdown (dv left at the guess).
bool RunGaussSeidelPcg(const FabricModel& model, const FabricState& state,
                       const StepOptions& options, FabricWorkspace* ws, CgReport* report) {
  const int n = model.num_particles;
  const GaussSeidelPreconditioner& gs = ws->gauss_seidel;
  const std::vector<Eigen::Matrix3d>& a = ws->system;
  const std::vector<double>& scalars = ws->system_scalars;
  FabricWorkspace::SplitVectors& v = ws->split;
  // s = filter(rhs); q = filter(rhs - A dv), padded.
  FilteredMultiply(model, state, *ws, ws->dv, &ws->q);
  double rhs_norm2 = 0.0;
  for (int p = 0; p < n; ++p) {
    if (IsFree(state, p)) {
      v.s.SetRow(p, ws->rhs.segment<3>(3 * p));
      v.q.SetRow(p, ws->rhs.segment<3>(3 * p) - ws->q.segment<3>(3 * p));
      rhs_norm2 += ws->rhs.segment<3>(3 * p).squaredNorm();
    } else {
      v.s.SetRow(p, Eigen::Vector3d::Zero());
      v.q.SetRow(p, Eigen::Vector3d::Zero());
    }
  }
  gs.ForwardSolve(a, scalars, v.s, &v.z);
  const double delta0 = gs.MultiplyDiagonal(v.z, &v.t);
  const PcgStart start = StartPcg(model, state, delta0, rhs_norm2, v.q.vec().allFinite(), ws, report);
  if (start != PcgStart::kIterate) return start == PcgStart::kBreakdown;
  gs.ForwardSolve(a, scalars, v.q, &v.r);  // r~ = (D_w + L)^-1 r0
  // CG runs on y~ = (D_w + U) y from 0, but y itself is kept: y = sum alpha_k (D_w + U)^-1 c_k,
  // and the product leaves (D_w + U)^-1 c_k in t. That saves the backward sweep y~ -> y.
  v.y.SetZero();
  const bool breakdown = Iterate(
      [&](const PaddedVector& c, PaddedVector* q) { return gs.MultiplySplit(a, scalars, c, &v.t, &v.z, q); },
      [&](const PaddedVector& r, PaddedVector* z) { return gs.MultiplyDiagonal(r, z); },
      [&](double alpha) { v.y.vec() += alpha * v.t.vec(); }, delta0, options,
      CgVectors<PaddedVector>{&v.r, &v.c, &v.q, &v.s}, report);
  if (breakdown) return true;
  v.y.AddRowsTo(&ws->dv);
  return false;
}

}  // namespace

CgReport ImplicitEulerStep(const FabricModel& model, const StepOptions& options,
                           FabricState* state, FabricWorkspace* ws) {
  const double h = options.dt_s;
  const int n = model.num_particles;

  // Forces and the system matrix A = M - h df/dv - h^2 df/dx, starting from its constant part
  // (mass, bending, linear drag), built once per model and step.
  ForceSink sink;
  sink.force_N = &ws->force_N;
  sink.system = &ws->system;
  sink.dx_scale = -h * h;
  sink.dv_scale = -h;
  sink.dfdx_v = &ws->dfdx_v;
  sink.v = &state->v_W_m_per_s;
  if (ws->system_base_model != &model || ws->system_base_dt_s != h) BuildSystemBase(model, h, &sink, ws);
  ResetSystem(model.product_rows, n, ws);
  ws->force_N.setZero();
  ws->dfdx_v.setZero();
  sink.constant_jacobians_added = true;
  AccumulateForces(model, *state, &sink);
  AddAnchorSpringForces(model, *state, &sink);
  ws->rhs = h * (ws->force_N + h * ws->dfdx_v);

  // Initial guess carries the prescribed velocity change (z).
  for (int p = 0; p < n; ++p) {
    if (IsFree(*state, p)) {
      // Warm start: the previous step's velocity change is a good guess for a smooth motion.
      if (!options.cg_warm_start) ws->dv.segment<3>(3 * p).setZero();
    } else {
      ws->dv.segment<3>(3 * p) = state->prescribed_v_W_m_per_s.segment<3>(3 * p) -
                                 state->v_W_m_per_s.segment<3>(3 * p);
    }
  }

  const ParticleMode* mode = state->mode.data();
  bool gauss_seidel_ok = true;
  if (options.preconditioner == Preconditioner::kMultilevel) {
    ws->multilevel.Update(model, *state, ws->system);
  } else if (options.preconditioner == Preconditioner::kGaussSeidel) {
    HAPTEX_TEXTILE_DEMAND(ws->gauss_seidel.rows() == n);  // a workspace built for it
    gauss_seidel_ok = ws->gauss_seidel.Update(ws->system, options.ssor_omega,
                                              [mode](int r) { return mode[r] == ParticleMode::kFree; });
  } else {
    UpdateBlockJacobi(model, ws);
  }

  // Modified PCG; on a preconditioner breakdown retry from the same guess with block Jacobi.
  ws->dv0 = ws->dv;
  CgReport report;
  Preconditioner pc = options.preconditioner;
  bool breakdown = pc == Preconditioner::kGaussSeidel
                       ? (!gauss_seidel_ok || RunGaussSeidelPcg(model, *state, options, ws, &report))
                       : RunPcg(model, *state, options, pc, ws, &report);
  if (breakdown && pc != Preconditioner::kBlockJacobi) {
    report.preconditioner_fallback = true;
    ws->dv = ws->dv0;
    pc = Preconditioner::kBlockJacobi;
    UpdateBlockJacobi(model, ws);
    breakdown = RunPcg(model, *state, options, pc, ws, &report);
  }
  if (breakdown) report.converged = false;

  report.finite = report.finite && ws->dv.allFinite();
  if (!report.finite) {
    ws->dv.setZero();  // never warm-start from garbage
    return report;
  }

  // Update: v += dv, x += h v.
  state->v_W_m_per_s += ws->dv;
  state->x_W_m += h * state->v_W_m_per_s;
  state->time_s += h;
  return report;
}

}  // namespace haptex::textile
