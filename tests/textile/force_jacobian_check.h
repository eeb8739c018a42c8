#pragma once
// Shared assertion for the force tests: analytic Jacobians against finite differences.

#include <algorithm>

#include <gtest/gtest.h>

#include "libs/textile/validation.h"
#include "tests/textile/textile_test_util.h"

namespace haptex::textile::testing {

/// Random deformation of the rest state (seeded), with random velocities.
using validation::Perturb;

/// Expects |analytic - fd| <= tol * max|fd| (elementwise max).
inline void ExpectJacobianNear(const Eigen::MatrixXd& analytic, const Eigen::MatrixXd& fd, double tol,
                               const char* what) {
  const double scale = std::max(fd.cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LE((analytic - fd).cwiseAbs().maxCoeff(), tol * scale) << what;
}

}  // namespace haptex::textile::testing
