#pragma once
// Shared assertion for the force tests: analytic Jacobians against finite differences.

#include <algorithm>
#include <random>

#include <gtest/gtest.h>

#include "tests/textile/textile_test_util.h"

namespace haptex::textile::testing {

/// Random deformation of the rest state (seeded), with random velocities.
inline void Perturb(FabricState* s, double dx_m, double dv_m_per_s, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (Eigen::Index i = 0; i < s->x_W_m.size(); ++i) {
    s->x_W_m[i] += dx_m * uniform(rng);
    s->v_W_m_per_s[i] = dv_m_per_s * uniform(rng);
  }
}

/// Expects |analytic - fd| <= tol * max|fd| (elementwise max).
inline void ExpectJacobianNear(const Eigen::MatrixXd& analytic, const Eigen::MatrixXd& fd, double tol,
                               const char* what) {
  const double scale = std::max(fd.cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LE((analytic - fd).cwiseAbs().maxCoeff(), tol * scale) << what;
}

}  // namespace haptex::textile::testing
