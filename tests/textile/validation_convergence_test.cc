// Validation 3: convergence. Errors must fall as the resolution goes up (static cantilever at
// lambda = w l^3 / B = 8, whose exact chord angle is 41.49 deg from the heavy elastica) and as dt
// goes down (dynamic swing of the same cantilever released from horizontal, against dt = 0.125 ms).

#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "libs/textile/fabric_stepper.h"
#include "libs/textile/kes_material.h"
#include "tests/textile/fabric_textproto.h"
#include "tests/textile/textile_test_util.h"

namespace haptex::textile {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct Cantilever {
  FabricModel model;
  FabricState state;
  int n;
};

Cantilever MakeCantilever(const FabricMaterial& material, double l, int n) {
  FabricModel model = BuildFabricModel(material, {l * (n + 1) / n, 0.02, n + 2, 3});
  FabricState s = MakeRestState(model);
  for (int j = 0; j < 3; ++j) {
    s.Fix(model.mesh.Index(0, j));
    s.Fix(model.mesh.Index(1, j));
  }
  return {std::move(model), std::move(s), n};
}

double ChordAngleDeg(const Cantilever& c) {
  double angle = 0.0;
  for (int j = 0; j < 3; ++j) {
    const Eigen::Vector3d d = c.state.x(c.model.mesh.Index(c.n + 1, j)) - c.state.x(c.model.mesh.Index(1, j));
    angle += std::atan2(-d.z(), d.x()) * 180.0 / kPi / 3.0;
  }
  return angle;
}

class ConvergenceTest : public ::testing::Test {
 protected:
  FabricMaterial material_ = MaterialFromKes(testing::LoadDatabaseFabric("wang2011_royal_target"));
  // Overhang with lambda = 8: chord angle 41.49 deg (docs/physics-reference.md section 4.2,
  // computed by docs/derivations/heavy_elastica.py).
  double l_ = std::cbrt(8.0 * material_.bending_warp_Nm / (material_.density_kg_per_m2 * 9.81));
};

TEST_F(ConvergenceTest, StaticErrorFallsWithResolution) {
  std::vector<double> errors;
  for (int n : {4, 8, 16, 32}) {
    Cantilever c = MakeCantilever(material_, l_, n);
    StepOptions opt;
    opt.dt_s = 0.02;
    opt.cg_tolerance = 1e-9;
    opt.cg_max_iterations = 5000;
    FabricStepper stepper(c.model, opt);
    testing::RunToRest(&stepper, &c.state, 20000, 1e-7);
    const double err = std::abs(ChordAngleDeg(c) - 41.49);
    std::printf("[table] resolution n=%d cells: chord %.3f deg (exact 41.49), error %.3f deg\n", n, ChordAngleDeg(c),
                err);
    errors.push_back(err);
  }
  for (std::size_t i = 1; i < errors.size(); ++i) EXPECT_LT(errors[i], errors[i - 1]);
}

TEST_F(ConvergenceTest, DynamicErrorFallsWithTimeStep) {
  const double t_end = 0.2;
  auto tip_at_end = [&](double dt) {
    Cantilever c = MakeCantilever(material_, l_, 10);
    StepOptions opt;
    opt.dt_s = dt;
    opt.cg_tolerance = 1e-10;
    opt.cg_max_iterations = 5000;
    FabricStepper stepper(c.model, opt);
    const int steps = static_cast<int>(std::lround(t_end / dt));
    for (int i = 0; i < steps; ++i) stepper.Step(&c.state);
    return Eigen::Vector3d(c.state.x(c.model.mesh.Index(11, 1)));
  };
  const Eigen::Vector3d reference = tip_at_end(0.000125);
  std::vector<double> errors;
  for (double dt : {0.008, 0.004, 0.002, 0.001}) {
    const double err = (tip_at_end(dt) - reference).norm();
    std::printf("[table] dt %.3f ms: tip error at t=0.2 s %.4f mm\n", 1e3 * dt, 1e3 * err);
    errors.push_back(err);
  }
  for (std::size_t i = 1; i < errors.size(); ++i) EXPECT_LT(errors[i], errors[i - 1]);
  // First order: halving dt roughly halves the error.
  EXPECT_LT(errors.back(), 0.25 * errors.front());
}

}  // namespace
}  // namespace haptex::textile
