#include "libs/textile/fabric_forces.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <vector>

#include <Eigen/Geometry>

#include "libs/textile/external_force.h"

namespace haptex::textile {
namespace {

// Full unrolling of the fixed 3- and 9-long element loops (-O2 keeps them as loops over stack
// arrays, several times slower here).
#define HAPTEX_UNROLL _Pragma("GCC unroll 9")

// The per-force functions (tensile_force.cc, shear_force.cc, bending_force.cc, drag_force.cc)
// are the reference; this file evaluates the same forces and Jacobians in one pass per element,
// writing each system block once (dx and dv terms combined) and computing (df/dx) v per element
// instead of per block. tests/textile/fabric_forces_test.cc checks the two agree.

// One tensile direction of a triangle: d = sum w_k x_k. Adds -A (sigma + c dir.d_dot) w_k dir
// to f. Its Jacobian blocks are A_kl = w_k w_l (beta dir dir^T + alpha I) (dx and dv combined,
// scaled by the sink), and -A kx d_dot (times w_k) is its (df/dx) v. Everything is zero for a
// collapsed element (no defined direction), so the caller adds the terms unconditionally.
// Plain arrays: the element math stays in registers (Eigen's 3x3 temporaries did not).
struct Direction {
  double dir[3] = {0.0, 0.0, 0.0};
  double beta = 0.0, alpha = 0.0;
  double kx_ddot[3] = {0.0, 0.0, 0.0};
};

inline double Dot3(const double* a, const double* b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

// A 3x3 block as its 9 column-major entries: 4 pairs (SSE2 registers, or the target's 2-wide
// vectors: a GCC/Clang vector extension, no ISA beyond the baseline) and the last entry.
using V2 = double __attribute__((vector_size(16)));
struct Outer {
  V2 v[4];
  double last;
};

// p q^T = ExpandColumn(p) * ExpandRow(q) entrywise (column-major: entry i + 3 j is p_i q_j).
inline Outer ExpandColumn(const double p[3]) {
  return {{V2{p[0], p[1]}, V2{p[2], p[0]}, V2{p[1], p[2]}, V2{p[0], p[1]}}, p[2]};
}
inline Outer ExpandRow(const double q[3]) {
  return {{V2{q[0], q[0]}, V2{q[0], q[1]}, V2{q[1], q[1]}, V2{q[2], q[2]}}, q[2]};
}
inline Outer Product(const Outer& a, const Outer& b) {
  return {{a.v[0] * b.v[0], a.v[1] * b.v[1], a.v[2] * b.v[2], a.v[3] * b.v[3]}, a.last * b.last};
}
inline void AddScaled(double s, const Outer& a, Outer* m) {
  HAPTEX_UNROLL
  for (int i = 0; i < 4; ++i) m->v[i] += s * a.v[i];
  m->last += s * a.last;
}
// block += m (a Matrix3d's data: 8-byte aligned only).
inline void AddTo(const Outer& m, double* block) {
  HAPTEX_UNROLL
  for (int i = 0; i < 4; ++i) {
    V2 b;
    std::memcpy(&b, block + 2 * i, sizeof b);
    b += m.v[i];
    std::memcpy(block + 2 * i, &b, sizeof b);
  }
  block[8] += m.last;
}

inline void TensileDirection(double area, const std::array<double, 3>& w, const StrainCurve& curve,
                             double damping_s, const double d[3], const double d_dot[3],
                             bool jacobians, double dx_scale, double dv_scale, double f[3][3],
                             Direction* out) {
  const double len = std::sqrt(Dot3(d, d));
  if (!(len > 1e-12)) return;  // collapsed element: no defined direction
  const double inv_len = 1.0 / len;
  double* dir = out->dir;
  HAPTEX_UNROLL
  for (int i = 0; i < 3; ++i) dir[i] = d[i] * inv_len;
  double sigma = 0.0, slope = 0.0;
  curve.Evaluate(len - 1.0, &sigma, &slope);
  const double c = damping_s * slope;
  const double dir_ddot = Dot3(dir, d_dot);
  const double total = sigma + c * dir_ddot;
  HAPTEX_UNROLL
  for (std::size_t k = 0; k < 3; ++k) {
    const double s = area * total * w[k];
    HAPTEX_UNROLL
    for (int i = 0; i < 3; ++i) f[k][i] -= s * dir[i];
  }
  if (!jacobians) return;
  // kx = slope ddT + t (I - ddT), t = max(sigma, 0) / len; kv = c ddT.
  const double t = std::max(sigma, 0.0) * inv_len;
  out->beta = -area * (dx_scale * (slope - t) + dv_scale * c);
  out->alpha = -area * dx_scale * t;
  const double along = (slope - t) * dir_ddot;
  HAPTEX_UNROLL
  for (int i = 0; i < 3; ++i) out->kx_ddot[i] = -area * (along * dir[i] + t * d_dot[i]);
}

// beta dir dir^T + alpha I of one direction (zero for a collapsed element).
inline Outer DirectionStiffness(const Direction& d) {
  double bd[3];
  HAPTEX_UNROLL
  for (int i = 0; i < 3; ++i) bd[i] = d.beta * d.dir[i];
  Outer k = Product(ExpandColumn(bd), ExpandRow(d.dir));
  k.v[0] += V2{d.alpha, 0.0};
  k.v[2] += V2{d.alpha, 0.0};
  k.last += d.alpha;
  return k;
}

// Tensile (warp, weft), shear and quadratic drag of every triangle; each of its 9 system blocks
// is one sum of rank-one terms, written once.
void AddTriangleForces(const FabricModel& model, const Eigen::VectorXd& x,
                       const Eigen::VectorXd& v, ForceSink* sink) {
  const bool jac = sink->wants_jacobians();
  const double dxs = sink->dx_scale, dvs = sink->dv_scale;
  const double stretch_s = model.options.damping.stretch_s;
  const double shear_s = model.options.damping.shear_s;
  const DragOptions& drag = model.options.drag;
  const double q = 0.5 * drag.air_density_kg_per_m3 * drag.quadratic_coefficient;
  const FabricMaterial& mat = model.material;
  const double* xp = x.data();
  const double* vp = v.data();
  double* fp = sink->force_N->data();
  double* dfv = jac ? sink->dfdx_v->data() : nullptr;
  Eigen::Matrix3d* system = jac ? sink->system->data() : nullptr;
  const std::size_t num_triangles = model.triangles.size();
  for (std::size_t t = 0; t < num_triangles; ++t) {
    const TriangleElement& e = model.triangles[t];
    const double area = e.area_m2;
    const double* xk[3] = {xp + 3 * e.p[0], xp + 3 * e.p[1], xp + 3 * e.p[2]};
    const double* vk[3] = {vp + 3 * e.p[0], vp + 3 * e.p[1], vp + 3 * e.p[2]};
    double u[3], w[3], u_dot[3], w_dot[3];
    HAPTEX_UNROLL
    for (int i = 0; i < 3; ++i) {
      u[i] = e.a[0] * xk[0][i] + e.a[1] * xk[1][i] + e.a[2] * xk[2][i];
      w[i] = e.b[0] * xk[0][i] + e.b[1] * xk[1][i] + e.b[2] * xk[2][i];
      u_dot[i] = e.a[0] * vk[0][i] + e.a[1] * vk[1][i] + e.a[2] * vk[2][i];
      w_dot[i] = e.b[0] * vk[0][i] + e.b[1] * vk[1][i] + e.b[2] * vk[2][i];
    }
    double f[3][3] = {{0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}};

    // Tensile, warp and weft.
    Direction warp, weft;
    TensileDirection(area, e.a, mat.tensile_warp, stretch_s, u, u_dot, jac, dxs, dvs, f, &warp);
    TensileDirection(area, e.b, mat.tensile_weft, stretch_s, w, w_dot, jac, dxs, dvs, f, &weft);

    // Shear: gamma = U.V, d gamma / d x_k = g_k = a_k V + b_k U.
    double g[3][3];
    double gamma_dot = 0.0;
    HAPTEX_UNROLL
    for (std::size_t k = 0; k < 3; ++k) {
      HAPTEX_UNROLL
      for (int i = 0; i < 3; ++i) g[k][i] = e.a[k] * w[i] + e.b[k] * u[i];
      gamma_dot += Dot3(g[k], vk[k]);
    }
    double tau = 0.0, shear_slope = 0.0;
    mat.shear.Evaluate(Dot3(u, w), &tau, &shear_slope);
    const double shear_c = shear_s * shear_slope;
    const double shear_total = tau + shear_c * gamma_dot;
    const double shear_f = area * shear_total;
    HAPTEX_UNROLL
    for (std::size_t k = 0; k < 3; ++k) {
      HAPTEX_UNROLL
      for (int i = 0; i < 3; ++i) f[k][i] -= shear_f * g[k][i];
    }

    // Quadratic drag on the normal velocity (Jacobian in v only): dq n n^T per block.
    double n[3] = {0.0, 0.0, 0.0};
    double dq = 0.0;
    if (q > 0.0) {
      const double e1[3] = {xk[1][0] - xk[0][0], xk[1][1] - xk[0][1], xk[1][2] - xk[0][2]};
      const double e2[3] = {xk[2][0] - xk[0][0], xk[2][1] - xk[0][1], xk[2][2] - xk[0][2]};
      const double cross[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                               e1[0] * e2[1] - e1[1] * e2[0]};
      const double twice_area = std::sqrt(Dot3(cross, cross));
      if (twice_area > 1e-14) {
        const double inv_twice_area = 1.0 / twice_area;
        HAPTEX_UNROLL
        for (int i = 0; i < 3; ++i) n[i] = cross[i] * inv_twice_area;
        double vm[3];
        HAPTEX_UNROLL
        for (int i = 0; i < 3; ++i) vm[i] = (vk[0][i] + vk[1][i] + vk[2][i]) / 3.0;
        const double vn = Dot3(n, vm);
        const double drag_area = 0.5 * twice_area;
        const double fc = -q * drag_area * vn * std::abs(vn) / 3.0;
        HAPTEX_UNROLL
        for (std::size_t k = 0; k < 3; ++k) {
          HAPTEX_UNROLL
          for (int i = 0; i < 3; ++i) f[k][i] += fc * n[i];
        }
        dq = dvs * (-q * drag_area * 2.0 * std::abs(vn) / 9.0);
      }
    }

    HAPTEX_UNROLL
    for (std::size_t k = 0; k < 3; ++k) {
      double* fk = fp + 3 * e.p[k];
      HAPTEX_UNROLL
      for (int i = 0; i < 3; ++i) fk[i] += f[k][i];
    }
    if (!jac) continue;

    // (df/dx) v per particle.
    const double shear_kx = -area * shear_slope * gamma_dot;
    const double shear_sys = -area * (dxs * shear_slope + dvs * shear_c);
    HAPTEX_UNROLL
    for (std::size_t k = 0; k < 3; ++k) {
      double* dk = dfv + 3 * e.p[k];
      HAPTEX_UNROLL
      for (int i = 0; i < 3; ++i) {
        dk[i] += shear_kx * g[k][i] + e.a[k] * warp.kx_ddot[i] + e.b[k] * weft.kx_ddot[i];
      }
    }

    // Blocks (k, l) = shear_sys g_k g_l^T + a_k a_l K_warp + b_k b_l K_weft + dq n n^T, with
    // K = beta dir dir^T + alpha I; on a grid half the weight products are zero (skipped).
    Outer shear_p[3], shear_q[3];
    HAPTEX_UNROLL
    for (int k = 0; k < 3; ++k) {
      double sg[3];
      HAPTEX_UNROLL
      for (int i = 0; i < 3; ++i) sg[i] = shear_sys * g[k][i];
      shear_p[k] = ExpandColumn(sg);
      shear_q[k] = ExpandRow(g[k]);
    }
    const Outer k_warp = DirectionStiffness(warp);
    const Outer k_weft = DirectionStiffness(weft);
    const bool drag_active = dq != 0.0;
    double dn[3];
    HAPTEX_UNROLL
    for (int i = 0; i < 3; ++i) dn[i] = dq * n[i];
    const Outer k_drag = Product(ExpandColumn(dn), ExpandRow(n));
    const auto& slots = model.triangle_slots[t];
    HAPTEX_UNROLL
    for (std::size_t k = 0; k < 3; ++k) {
      HAPTEX_UNROLL
      for (std::size_t l = 0; l < 3; ++l) {
        Outer m = Product(shear_p[k], shear_q[l]);
        const double aa = e.a[k] * e.a[l], bb = e.b[k] * e.b[l];
        if (aa != 0.0) AddScaled(aa, k_warp, &m);
        if (bb != 0.0) AddScaled(bb, k_weft, &m);
        if (drag_active) AddScaled(1.0, k_drag, &m);
        AddTo(m, system[static_cast<std::size_t>(slots[k * 3 + l])].data());
      }
    }
  }
}

// Volino's linear bending with damping; the constant Jacobian blocks only when asked for.
void AddBending(const FabricModel& model, const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                ForceSink* sink) {
  const double damping_s = model.options.damping.bend_s;
  const bool jac = sink->wants_jacobians();
  const bool blocks = jac && !sink->constant_jacobians_added;
  for (std::size_t b = 0; b < model.bends.size(); ++b) {
    const BendElement& e = model.bends[b];
    Eigen::Vector3d r = Eigen::Vector3d::Zero(), r_dot = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < 3; ++k) {
      r += e.alpha[k] * x.segment<3>(3 * e.p[k]);
      r_dot += e.alpha[k] * v.segment<3>(3 * e.p[k]);
    }
    const Eigen::Vector3d f = -e.lambda_N_per_m * (r + damping_s * r_dot);
    const Eigen::Vector3d kv = -e.lambda_N_per_m * r_dot;
    for (std::size_t k = 0; k < 3; ++k) {
      sink->force_N->segment<3>(3 * e.p[k]) += e.alpha[k] * f;
      if (jac) sink->dfdx_v->segment<3>(3 * e.p[k]) += e.alpha[k] * kv;
    }
    if (blocks) {
      const double scale = -e.lambda_N_per_m * (sink->dx_scale + sink->dv_scale * damping_s);
      for (std::size_t k = 0; k < 3; ++k) {
        for (std::size_t l = 0; l < 3; ++l) {
          (*sink->system)[static_cast<std::size_t>(model.bend_slots[b][k * 3 + l])]
              .diagonal().array() += scale * e.alpha[k] * e.alpha[l];
        }
      }
    }
  }
}

// Linear (viscous) drag: -c A v per particle; its Jacobian is constant.
void AddLinearDrag(const FabricModel& model, const Eigen::VectorXd& v, ForceSink* sink) {
  const double c0 = model.options.drag.linear_N_s_per_m3;
  if (!(c0 > 0.0)) return;
  const bool blocks = sink->wants_jacobians() && !sink->constant_jacobians_added;
  for (int p = 0; p < model.num_particles; ++p) {
    const double c = c0 * model.area_m2[p];
    sink->force_N->segment<3>(3 * p) -= c * v.segment<3>(3 * p);
    if (blocks) {
      const int slot = model.pattern.diag_slot[static_cast<std::size_t>(p)];
      (*sink->system)[static_cast<std::size_t>(slot)].diagonal().array() -= sink->dv_scale * c;
    }
  }
}

}  // namespace

void AccumulateForces(const FabricModel& model, const FabricState& state, ForceSink* sink) {
  const Eigen::VectorXd& x = state.x_W_m;
  const Eigen::VectorXd& v = state.v_W_m_per_s;
  AddTriangleForces(model, x, v, sink);
  AddBending(model, x, v, sink);
  AddLinearDrag(model, v, sink);
  AddExternalForces(model, state, sink);
}

void AddConstantJacobians(const FabricModel& model, ForceSink* sink) {
  const double damping_s = model.options.damping.bend_s;
  std::vector<Eigen::Matrix3d>& system = *sink->system;
  for (std::size_t b = 0; b < model.bends.size(); ++b) {
    const BendElement& e = model.bends[b];
    const double scale = -e.lambda_N_per_m * (sink->dx_scale + sink->dv_scale * damping_s);
    for (std::size_t k = 0; k < 3; ++k) {
      for (std::size_t l = 0; l < 3; ++l) {
        system[static_cast<std::size_t>(model.bend_slots[b][k * 3 + l])].diagonal().array() +=
            scale * e.alpha[k] * e.alpha[l];
      }
    }
  }
  const double c0 = model.options.drag.linear_N_s_per_m3;
  if (c0 > 0.0) {
    for (int p = 0; p < model.num_particles; ++p) {
      system[static_cast<std::size_t>(model.pattern.diag_slot[static_cast<std::size_t>(p)])]
          .diagonal().array() -= sink->dv_scale * c0 * model.area_m2[p];
    }
  }
}

}  // namespace haptex::textile
