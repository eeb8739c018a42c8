#include "libs/textile/drag_force.h"

#include <cmath>

#include <Eigen/Geometry>

namespace haptex::textile {

void AddDragForces(const FabricModel& model, const Eigen::VectorXd& x, const Eigen::VectorXd& v, ForceSink* sink) {
  const DragOptions& o = model.options.drag;
  if (o.linear_N_s_per_m3 > 0.0) {
    for (int p = 0; p < model.num_particles; ++p) {
      const double c = o.linear_N_s_per_m3 * model.area_m2[p];
      sink->AddForce(p, -c * v.segment<3>(3 * p));
      if (sink->wants_jacobians()) {
        sink->AddDv(model.pattern.diag_slot[static_cast<std::size_t>(p)], -c * Eigen::Matrix3d::Identity());
      }
    }
  }
  const double q = 0.5 * o.air_density_kg_per_m3 * o.quadratic_coefficient;
  if (q <= 0.0) return;
  for (std::size_t t = 0; t < model.triangles.size(); ++t) {
    const TriangleElement& e = model.triangles[t];
    const Eigen::Vector3d x0 = x.segment<3>(3 * e.p[0]);
    const Eigen::Vector3d cross = (x.segment<3>(3 * e.p[1]) - x0).cross(x.segment<3>(3 * e.p[2]) - x0);
    const double twice_area = cross.norm();
    if (!(twice_area > 1e-14)) continue;
    const Eigen::Vector3d n = cross / twice_area;
    const Eigen::Vector3d vm = (v.segment<3>(3 * e.p[0]) + v.segment<3>(3 * e.p[1]) + v.segment<3>(3 * e.p[2])) / 3.0;
    const double vn = n.dot(vm);
    const double area = 0.5 * twice_area;
    const Eigen::Vector3d f_corner = (-q * area * vn * std::abs(vn) / 3.0) * n;
    for (std::size_t k = 0; k < 3; ++k) sink->AddForce(e.p[k], f_corner);
    if (!sink->wants_jacobians()) continue;
    // d f_k / d v_l = -q A 2|vn| n n^T / 9.
    const Eigen::Matrix3d jac = (-q * area * 2.0 * std::abs(vn) / 9.0) * (n * n.transpose());
    for (std::size_t k = 0; k < 9; ++k) sink->AddDv(model.triangle_slots[t][k], jac);
  }
}

}  // namespace haptex::textile
