#include "libs/textile/tensile_force.h"

#include <algorithm>

namespace haptex::textile {
namespace {

// One direction (warp with weights a, or weft with weights b) of one triangle.
void AddDirection(const TriangleElement& e, const std::array<int, 9>& slots, const std::array<double, 3>& w,
                  const StrainCurve& curve, double damping_s, const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                  ForceSink* sink) {
  Eigen::Vector3d d = Eigen::Vector3d::Zero(), d_dot = Eigen::Vector3d::Zero();
  for (int k = 0; k < 3; ++k) {
    d += w[static_cast<std::size_t>(k)] * x.segment<3>(3 * e.p[static_cast<std::size_t>(k)]);
    d_dot += w[static_cast<std::size_t>(k)] * v.segment<3>(3 * e.p[static_cast<std::size_t>(k)]);
  }
  const double len = d.norm();
  if (!(len > 1e-12)) return;  // collapsed element: no defined direction
  const Eigen::Vector3d dir = d / len;
  double sigma = 0.0, slope = 0.0;
  curve.Evaluate(len - 1.0, &sigma, &slope);
  const double c = damping_s * slope;
  const double total = sigma + c * dir.dot(d_dot);
  for (int k = 0; k < 3; ++k) {
    sink->AddForce(e.p[static_cast<std::size_t>(k)], -e.area_m2 * total * w[static_cast<std::size_t>(k)] * dir);
  }
  if (!sink->wants_jacobians()) return;
  const Eigen::Matrix3d ddT = dir * dir.transpose();
  const Eigen::Matrix3d kx = slope * ddT + (std::max(sigma, 0.0) / len) * (Eigen::Matrix3d::Identity() - ddT);
  const Eigen::Matrix3d kv = c * ddT;
  for (int k = 0; k < 3; ++k) {
    for (int l = 0; l < 3; ++l) {
      const double s = -e.area_m2 * w[static_cast<std::size_t>(k)] * w[static_cast<std::size_t>(l)];
      const int slot = slots[static_cast<std::size_t>(k * 3 + l)];
      sink->AddDx(slot, e.p[static_cast<std::size_t>(k)], e.p[static_cast<std::size_t>(l)], s * kx);
      sink->AddDv(slot, s * kv);
    }
  }
}

}  // namespace

void AddTensileForces(const FabricModel& model, const Eigen::VectorXd& x, const Eigen::VectorXd& v, ForceSink* sink) {
  const double damping_s = model.options.damping.stretch_s;
  for (std::size_t t = 0; t < model.triangles.size(); ++t) {
    const TriangleElement& e = model.triangles[t];
    AddDirection(e, model.triangle_slots[t], e.a, model.material.tensile_warp, damping_s, x, v, sink);
    AddDirection(e, model.triangle_slots[t], e.b, model.material.tensile_weft, damping_s, x, v, sink);
  }
}

}  // namespace haptex::textile
