#include "libs/textile/fabric_strain.h"

#include <algorithm>
#include <limits>

namespace haptex::textile {

double LargestTensileStrain(const FabricModel& model, const Eigen::VectorXd& x) {
  if (model.triangles.empty()) return 0.0;
  double largest = -std::numeric_limits<double>::infinity();
  for (const TriangleElement& e : model.triangles) {
    Eigen::Vector3d u = Eigen::Vector3d::Zero(), v = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < 3; ++k) {
      const Eigen::Vector3d xk = x.segment<3>(3 * e.p[k]);
      u += e.a[k] * xk;
      v += e.b[k] * xk;
    }
    largest = std::max({largest, u.norm() - 1.0, v.norm() - 1.0});
  }
  return largest;
}

}  // namespace haptex::textile
