#include "libs/textile/shear_force.h"

namespace haptex::textile {

void AddShearForces(const FabricModel& model, const Eigen::VectorXd& x, const Eigen::VectorXd& v, ForceSink* sink) {
  const double damping_s = model.options.damping.shear_s;
  const StrainCurve& curve = model.material.shear;
  for (std::size_t t = 0; t < model.triangles.size(); ++t) {
    const TriangleElement& e = model.triangles[t];
    Eigen::Vector3d u = Eigen::Vector3d::Zero(), w = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < 3; ++k) {
      u += e.a[k] * x.segment<3>(3 * e.p[k]);
      w += e.b[k] * x.segment<3>(3 * e.p[k]);
    }
    std::array<Eigen::Vector3d, 3> g;
    double gamma_dot = 0.0;
    for (std::size_t k = 0; k < 3; ++k) {
      g[k] = e.a[k] * w + e.b[k] * u;
      gamma_dot += g[k].dot(v.segment<3>(3 * e.p[k]));
    }
    double tau = 0.0, slope = 0.0;
    curve.Evaluate(u.dot(w), &tau, &slope);
    const double c = damping_s * slope;
    const double total = tau + c * gamma_dot;
    for (std::size_t k = 0; k < 3; ++k) sink->AddForce(e.p[k], -e.area_m2 * total * g[k]);
    if (!sink->wants_jacobians()) continue;
    const auto& slots = model.triangle_slots[t];
    for (std::size_t k = 0; k < 3; ++k) {
      for (std::size_t l = 0; l < 3; ++l) {
        const Eigen::Matrix3d ggT = -e.area_m2 * g[k] * g[l].transpose();
        const int slot = slots[k * 3 + l];
        sink->AddDx(slot, e.p[k], e.p[l], slope * ggT);
        sink->AddDv(slot, c * ggT);
      }
    }
  }
}

}  // namespace haptex::textile
