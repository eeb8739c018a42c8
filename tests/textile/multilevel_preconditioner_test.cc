#include "libs/textile/multilevel_preconditioner.h"

#include <random>

#include <gtest/gtest.h>

#include "libs/textile/fabric_forces.h"
#include "libs/textile/fabric_stepper.h"
#include "libs/textile/kes_material.h"
#include "tests/textile/fabric_textproto.h"
#include "tests/textile/textile_test_util.h"

namespace haptex::textile {
namespace {

FabricModel DenimModel(int n) {
  return BuildFabricModel(MaterialFromKes(testing::LoadDatabaseFabric("wang2011_black_denim_11oz")), {0.2, 0.2, n, n});
}

FabricState Hanging(const FabricModel& model) {
  Placement pl;
  pl.axis_u_W = Eigen::Vector3d(0, 0, -1);
  pl.axis_v_W = Eigen::Vector3d(1, 0, 0);
  FabricState s = MakeRestState(model, pl);
  for (int p : testing::WarpRow(model, 0)) s.Fix(p);
  return s;
}

// Blocks of A = M - h df/dv - h^2 df/dx at the state, h = 10 ms.
std::vector<Eigen::Matrix3d> SystemBlocks(const FabricModel& model, const FabricState& s) {
  std::vector<Eigen::Matrix3d> blocks(static_cast<std::size_t>(model.pattern.num_blocks()), Eigen::Matrix3d::Zero());
  Eigen::VectorXd f = Eigen::VectorXd::Zero(3 * model.num_particles), fv = f;
  ForceSink sink;
  sink.force_N = &f;
  sink.system = &blocks;
  sink.dx_scale = -1e-4;
  sink.dv_scale = -1e-2;
  sink.dfdx_v = &fv;
  sink.v = &s.v_W_m_per_s;
  AccumulateForces(model, s, &sink);
  for (int p = 0; p < model.num_particles; ++p) {
    blocks[static_cast<std::size_t>(model.pattern.diag_slot[static_cast<std::size_t>(p)])] +=
        model.mass_kg[p] * Eigen::Matrix3d::Identity();
  }
  return blocks;
}

TEST(MultilevelPreconditionerTest, IsSymmetricPositiveDefiniteAndFiltered) {
  const FabricModel model = DenimModel(21);
  FabricState s = Hanging(model);
  FabricStepper stepper(model, {});
  for (int i = 0; i < 5; ++i) stepper.Step(&s);
  const auto blocks = SystemBlocks(model, s);
  MultilevelPreconditioner dut(model);
  EXPECT_GE(dut.num_levels(), 2);
  dut.Update(model, s, blocks);
  std::mt19937 rng(1);
  std::normal_distribution<double> normal;
  const int n3 = 3 * model.num_particles;
  for (int trial = 0; trial < 5; ++trial) {
    Eigen::VectorXd x(n3), y(n3), bx(n3), by(n3);
    for (int i = 0; i < n3; ++i) {
      x[i] = normal(rng);
      y[i] = normal(rng);
    }
    for (int p : testing::WarpRow(model, 0)) {
      x.segment<3>(3 * p).setZero();
      y.segment<3>(3 * p).setZero();
    }
    dut.Apply(x, &bx);
    dut.Apply(y, &by);
    EXPECT_NEAR(y.dot(bx), x.dot(by), 1e-9 * std::abs(x.dot(bx)));
    EXPECT_GT(x.dot(bx), 0.0);
    for (int p : testing::WarpRow(model, 0)) EXPECT_EQ(bx.segment<3>(3 * p).norm(), 0.0);
  }
}

TEST(MultilevelPreconditionerTest, NeedsFewerIterationsThanBlockJacobiForTheSameAnswer) {
  const FabricModel model = DenimModel(41);
  FabricState a = Hanging(model), b = a;
  StepOptions ml;
  ml.cg_tolerance = 1e-8;
  ml.cg_max_iterations = 5000;
  ml.cg_warm_start = false;
  StepOptions jacobi = ml;
  jacobi.preconditioner = Preconditioner::kBlockJacobi;
  FabricStepper sa(model, ml), sb(model, jacobi);
  int ia = 0, ib = 0;
  for (int i = 0; i < 5; ++i) {
    ia += sa.Step(&a).cg.iterations;
    ib += sb.Step(&b).cg.iterations;
  }
  EXPECT_LT(ia * 2, ib);
  EXPECT_LT((a.x_W_m - b.x_W_m).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_EQ(a.diagnostics.cg_not_converged, 0);
}

}  // namespace
}  // namespace haptex::textile
