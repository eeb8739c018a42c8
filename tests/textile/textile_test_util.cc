#include "tests/textile/textile_test_util.h"

#include <cmath>
#include <stdexcept>

namespace haptex::textile::testing {

void DenseForceAndJacobians(const FabricModel& model, const ForceFn& fn, const Eigen::VectorXd& x,
                            const Eigen::VectorXd& v, Eigen::VectorXd* f, Eigen::MatrixXd* dfdx,
                            Eigen::MatrixXd* dfdv) {
  const int n = model.num_particles;
  std::vector<Eigen::Matrix3d> blocks(static_cast<std::size_t>(model.pattern.num_blocks()));
  Eigen::VectorXd dfdx_v = Eigen::VectorXd::Zero(3 * n);
  auto run = [&](double sx, double sv) {
    for (auto& b : blocks) b.setZero();
    *f = Eigen::VectorXd::Zero(3 * n);
    ForceSink sink;
    sink.force_N = f;
    sink.system = &blocks;
    sink.dx_scale = sx;
    sink.dv_scale = sv;
    sink.dfdx_v = &dfdx_v;
    sink.v = &v;
    fn(model, x, v, &sink);
    Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(3 * n, 3 * n);
    for (int r = 0; r < n; ++r) {
      for (int k = model.pattern.row_start[static_cast<std::size_t>(r)];
           k < model.pattern.row_start[static_cast<std::size_t>(r) + 1]; ++k) {
        dense.block<3, 3>(3 * r, 3 * model.pattern.cols[static_cast<std::size_t>(k)]) =
            blocks[static_cast<std::size_t>(k)];
      }
    }
    return dense;
  };
  *dfdx = run(1.0, 0.0);
  *dfdv = run(0.0, 1.0);
}

Eigen::MatrixXd FiniteDifferenceJacobian(const FabricModel& model, const ForceFn& fn, const Eigen::VectorXd& x,
                                         const Eigen::VectorXd& v, bool wrt_v, double step) {
  const int n3 = 3 * model.num_particles;
  Eigen::MatrixXd jac(n3, n3);
  auto force = [&](const Eigen::VectorXd& xx, const Eigen::VectorXd& vv) {
    Eigen::VectorXd f = Eigen::VectorXd::Zero(n3);
    ForceSink sink;
    sink.force_N = &f;
    fn(model, xx, vv, &sink);
    return f;
  };
  for (int i = 0; i < n3; ++i) {
    Eigen::VectorXd xp = x, xm = x, vp = v, vm = v;
    if (wrt_v) {
      vp[i] += step;
      vm[i] -= step;
    } else {
      xp[i] += step;
      xm[i] -= step;
    }
    jac.col(i) = (force(xp, vp) - force(xm, vm)) / (2.0 * step);
  }
  return jac;
}

}  // namespace haptex::textile::testing
