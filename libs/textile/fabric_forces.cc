#include "libs/textile/fabric_forces.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <Eigen/Geometry>

#include "libs/textile/external_force.h"

namespace haptex::textile {
namespace {

// The per-force functions (tensile_force.cc, shear_force.cc, bending_force.cc, drag_force.cc)
// are the reference; this file evaluates the same forces and Jacobians in one pass per element,
// writing each system block once (dx and dv terms combined) and computing (df/dx) v per element
// instead of per block. tests/textile/fabric_forces_test.cc checks the two agree.

// One tensile direction of a triangle: d = sum w_k x_k. Adds -A (sigma + c dir.d_dot) w_k dir
// to f, and returns in `k_sys` the 3x3 block factor A_ij = w_i w_j k_sys (dx and dv combined,
// scaled by the sink) and in `kx_ddot` -A kx d_dot (the (df/dx) v factor, times w_k).
struct Direction {
  bool active = false;
  Eigen::Matrix3d k_sys;
  Eigen::Vector3d kx_ddot;
};

void TensileDirection(const TriangleElement& e, const std::array<double, 3>& w,
                      const StrainCurve& curve, double damping_s, const Eigen::Vector3d& d,
                      const Eigen::Vector3d& d_dot, bool jacobians, double dx_scale,
                      double dv_scale, std::array<Eigen::Vector3d, 3>* f, Direction* out) {
  out->active = false;
  const double len = d.norm();
  if (!(len > 1e-12)) return;  // collapsed element: no defined direction
  const Eigen::Vector3d dir = d / len;
  double sigma = 0.0, slope = 0.0;
  curve.Evaluate(len - 1.0, &sigma, &slope);
  const double c = damping_s * slope;
  const double total = sigma + c * dir.dot(d_dot);
  for (std::size_t k = 0; k < 3; ++k) (*f)[k] -= (e.area_m2 * total * w[k]) * dir;
  if (!jacobians) return;
  out->active = true;
  // kx = slope ddT + t (I - ddT), t = max(sigma, 0) / len; kv = c ddT.
  const double t = std::max(sigma, 0.0) / len;
  const Eigen::Matrix3d ddT = dir * dir.transpose();
  out->k_sys = (-e.area_m2) * ((dx_scale * (slope - t) + dv_scale * c) * ddT);
  out->k_sys.diagonal().array() += -e.area_m2 * dx_scale * t;
  out->kx_ddot = (-e.area_m2) * ((slope - t) * dir.dot(d_dot) * dir + t * d_dot);
}

// Tensile (warp, weft), shear and quadratic drag of every triangle.
void AddTriangleForces(const FabricModel& model, const Eigen::VectorXd& x,
                       const Eigen::VectorXd& v, ForceSink* sink) {
  const bool jac = sink->wants_jacobians();
  const double dxs = sink->dx_scale, dvs = sink->dv_scale;
  const double stretch_s = model.options.damping.stretch_s;
  const double shear_s = model.options.damping.shear_s;
  const DragOptions& drag = model.options.drag;
  const double q = 0.5 * drag.air_density_kg_per_m3 * drag.quadratic_coefficient;
  const FabricMaterial& mat = model.material;
  Eigen::VectorXd& force = *sink->force_N;
  for (std::size_t t = 0; t < model.triangles.size(); ++t) {
    const TriangleElement& e = model.triangles[t];
    std::array<Eigen::Vector3d, 3> xk, vk, f;
    for (std::size_t k = 0; k < 3; ++k) {
      xk[k] = x.segment<3>(3 * e.p[k]);
      vk[k] = v.segment<3>(3 * e.p[k]);
      f[k].setZero();
    }
    const Eigen::Vector3d u = e.a[0] * xk[0] + e.a[1] * xk[1] + e.a[2] * xk[2];
    const Eigen::Vector3d w = e.b[0] * xk[0] + e.b[1] * xk[1] + e.b[2] * xk[2];
    const Eigen::Vector3d u_dot = e.a[0] * vk[0] + e.a[1] * vk[1] + e.a[2] * vk[2];
    const Eigen::Vector3d w_dot = e.b[0] * vk[0] + e.b[1] * vk[1] + e.b[2] * vk[2];

    // Tensile, warp and weft.
    Direction warp, weft;
    TensileDirection(e, e.a, mat.tensile_warp, stretch_s, u, u_dot, jac, dxs, dvs, &f, &warp);
    TensileDirection(e, e.b, mat.tensile_weft, stretch_s, w, w_dot, jac, dxs, dvs, &f, &weft);

    // Shear: gamma = U.V, d gamma / d x_k = g_k = a_k V + b_k U.
    std::array<Eigen::Vector3d, 3> g;
    double gamma_dot = 0.0;
    for (std::size_t k = 0; k < 3; ++k) {
      g[k] = e.a[k] * w + e.b[k] * u;
      gamma_dot += g[k].dot(vk[k]);
    }
    double tau = 0.0, shear_slope = 0.0;
    mat.shear.Evaluate(u.dot(w), &tau, &shear_slope);
    const double shear_c = shear_s * shear_slope;
    const double shear_total = tau + shear_c * gamma_dot;
    for (std::size_t k = 0; k < 3; ++k) f[k] -= (e.area_m2 * shear_total) * g[k];

    // Quadratic drag on the normal velocity (Jacobian in v only).
    bool drag_active = false;
    Eigen::Matrix3d drag_sys = Eigen::Matrix3d::Zero();
    if (q > 0.0) {
      const Eigen::Vector3d cross = (xk[1] - xk[0]).cross(xk[2] - xk[0]);
      const double twice_area = cross.norm();
      if (twice_area > 1e-14) {
        const Eigen::Vector3d n = cross / twice_area;
        const Eigen::Vector3d vm = (vk[0] + vk[1] + vk[2]) / 3.0;
        const double vn = n.dot(vm);
        const double area = 0.5 * twice_area;
        const Eigen::Vector3d f_corner = (-q * area * vn * std::abs(vn) / 3.0) * n;
        for (std::size_t k = 0; k < 3; ++k) f[k] += f_corner;
        if (jac) {
          drag_active = true;
          drag_sys = (dvs * (-q * area * 2.0 * std::abs(vn) / 9.0)) * (n * n.transpose());
        }
      }
    }

    for (std::size_t k = 0; k < 3; ++k) force.segment<3>(3 * e.p[k]) += f[k];
    if (!jac) continue;

    // (df/dx) v per particle, and each system block once.
    const double shear_kx = -e.area_m2 * shear_slope * gamma_dot;
    const double shear_sys = -e.area_m2 * (dxs * shear_slope + dvs * shear_c);
    const auto& slots = model.triangle_slots[t];
    std::vector<Eigen::Matrix3d>& system = *sink->system;
    for (std::size_t k = 0; k < 3; ++k) {
      Eigen::Vector3d dv_k = shear_kx * g[k];
      if (warp.active) dv_k += e.a[k] * warp.kx_ddot;
      if (weft.active) dv_k += e.b[k] * weft.kx_ddot;
      sink->dfdx_v->segment<3>(3 * e.p[k]) += dv_k;
      for (std::size_t l = 0; l < 3; ++l) {
        Eigen::Matrix3d& block = system[static_cast<std::size_t>(slots[k * 3 + l])];
        block.noalias() += (shear_sys * g[k]) * g[l].transpose();
        if (warp.active) block += (e.a[k] * e.a[l]) * warp.k_sys;
        if (weft.active) block += (e.b[k] * e.b[l]) * weft.k_sys;
        if (drag_active) block += drag_sys;
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
