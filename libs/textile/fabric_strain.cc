#include "libs/textile/fabric_strain.h"

#include <algorithm>
#include <limits>

namespace haptex::textile {

void YarnVectors(const TriangleElement& e, const Eigen::VectorXd& x, Eigen::Vector3d* u, Eigen::Vector3d* v) {
  u->setZero();
  v->setZero();
  for (std::size_t k = 0; k < 3; ++k) {
    const Eigen::Vector3d xk = x.segment<3>(3 * e.p[k]);
    *u += e.a[k] * xk;
    *v += e.b[k] * xk;
  }
}

double LargestTensileStrain(const FabricModel& model, const Eigen::VectorXd& x) {
  if (model.triangles.empty()) return 0.0;
  double largest = -std::numeric_limits<double>::infinity();
  for (const TriangleElement& e : model.triangles) {
    Eigen::Vector3d u, v;
    YarnVectors(e, x, &u, &v);
    largest = std::max({largest, u.norm() - 1.0, v.norm() - 1.0});
  }
  return largest;
}

}  // namespace haptex::textile
