#include "libs/textile/bending_force.h"

namespace haptex::textile {

void AddBendingForces(const FabricModel& model, const Eigen::VectorXd& x, const Eigen::VectorXd& v, ForceSink* sink) {
  const double damping_s = model.options.damping.bend_s;
  for (std::size_t b = 0; b < model.bends.size(); ++b) {
    const BendElement& e = model.bends[b];
    Eigen::Vector3d r = Eigen::Vector3d::Zero(), r_dot = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < 3; ++k) {
      r += e.alpha[k] * x.segment<3>(3 * e.p[k]);
      r_dot += e.alpha[k] * v.segment<3>(3 * e.p[k]);
    }
    const Eigen::Vector3d f = -e.lambda_N_per_m * (r + damping_s * r_dot);
    for (std::size_t k = 0; k < 3; ++k) sink->AddForce(e.p[k], e.alpha[k] * f);
    if (!sink->wants_jacobians()) continue;
    const auto& slots = model.bend_slots[b];
    for (std::size_t k = 0; k < 3; ++k) {
      for (std::size_t l = 0; l < 3; ++l) {
        const double s = -e.lambda_N_per_m * e.alpha[k] * e.alpha[l];
        const int slot = slots[k * 3 + l];
        sink->AddDx(slot, e.p[k], e.p[l], s * Eigen::Matrix3d::Identity());
        sink->AddDv(slot, damping_s * s * Eigen::Matrix3d::Identity());
      }
    }
  }
}

}  // namespace haptex::textile
