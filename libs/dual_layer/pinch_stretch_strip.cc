#include "libs/dual_layer/pinch_stretch_strip.h"

#include <algorithm>
#include <cmath>

namespace haptex::dual_layer {

Strip PinchStretchStrip(const textile::FabricMaterial& material, double spacing_m) {
  const double width = 0.03, length = 0.08;
  const int nu = static_cast<int>(std::lround(length / spacing_m)) + 1;
  const int nv = static_cast<int>(std::lround(width / spacing_m)) + 1;
  Strip s{textile::BuildFabricModel(material, {length, width, nu, nv}), {}};
  textile::Placement placement;
  placement.origin_W = Eigen::Vector3d(-0.5 * width, 0.0, 0.0);
  placement.axis_u_W = Eigen::Vector3d(0, 0, -1);
  placement.axis_v_W = Eigen::Vector3d(1, 0, 0);
  s.state = textile::MakeRestState(s.model, placement);
  for (int j = 0; j < nv; ++j) s.state.Fix(s.model.mesh.Index(0, j));
  return s;
}

std::array<contact::FingerInput, 2> PinchStretchFingers(double t, const contact::ContactOptions& o) {
  const double r = o.thumb.radius_m + o.fabric_half_thickness_m;
  const double y = r + 0.003 - std::min(1.0, t / 0.3) * 0.0055;
  const double dz = 0.003 * std::clamp((t - 0.5) / 1.5, 0.0, 1.0);
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX();
  return {
      contact::FingerInput{true, contact::PoseFacing(Eigen::Vector3d(0, -y, -0.06 - dz), Eigen::Vector3d(0, 1, 0), x)},
      contact::FingerInput{true, contact::PoseFacing(Eigen::Vector3d(0, y, -0.06 - dz), Eigen::Vector3d(0, -1, 0), x)}};
}

}  // namespace haptex::dual_layer
