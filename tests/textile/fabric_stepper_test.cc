#include "libs/textile/fabric_stepper.h"

#include <limits>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "libs/textile/external_force.h"
#include "libs/textile/kes_material.h"
#include "tests/textile/textile_test_util.h"

namespace haptex::textile {
namespace {

class FabricStepperTest : public ::testing::Test {
 protected:
  FabricModel model_ = BuildFabricModel(MaterialFromKes(testing::CompositeDenim()), {0.1, 0.1, 6, 6});
};

TEST_F(FabricStepperTest, InvalidOptionsThrowAtConfiguration) {
  auto expect_throw = [&](StepOptions o, const char* text) {
    try {
      FabricStepper dut(model_, o);
      ADD_FAILURE() << "expected an exception mentioning " << text;
    } catch (const std::invalid_argument& e) {
      EXPECT_THAT(e.what(), ::testing::HasSubstr(text));
    }
  };
  StepOptions o;
  o.dt_s = 0.0;
  expect_throw(o, "dt_s");
  o.dt_s = -1.0;
  expect_throw(o, "dt_s");
  o.dt_s = std::numeric_limits<double>::quiet_NaN();
  expect_throw(o, "dt_s");
  o = {};
  o.cg_tolerance = 0.0;
  expect_throw(o, "cg_tolerance");
  o = {};
  o.cg_max_iterations = 0;
  expect_throw(o, "cg_max_iterations");
  o = {};
  o.max_speed_m_per_s = -1.0;
  expect_throw(o, "max_speed_m_per_s");
}

TEST_F(FabricStepperTest, NanIsRolledBackAndCounted) {
  FabricState s = MakeRestState(model_);
  FabricStepper dut(model_, {});
  dut.Step(&s);
  const FabricState good = s;
  SetPointLoad(3, Eigen::Vector3d(std::numeric_limits<double>::quiet_NaN(), 0, 0), &s);
  const StepResult r = dut.Step(&s);
  EXPECT_EQ(r.status, StepStatus::kNanRecovered);
  EXPECT_EQ(s.diagnostics.nan_events, 1);
  EXPECT_TRUE(s.x_W_m.allFinite());
  EXPECT_EQ(s.x_W_m, good.x_W_m);
  EXPECT_EQ(s.v_W_m_per_s.norm(), 0.0);
  EXPECT_STREQ(ToString(r.status), "nan_recovered");
}

TEST_F(FabricStepperTest, SpeedsAreCappedAndCounted) {
  FabricState s = MakeRestState(model_);
  StepOptions o;
  o.max_speed_m_per_s = 0.5;
  FabricStepper dut(model_, o);
  SetPointLoad(0, Eigen::Vector3d(0, 0, 50.0), &s);
  const StepResult r = dut.Step(&s);
  EXPECT_EQ(r.status, StepStatus::kSpeedCapped);
  EXPECT_GT(r.capped_particles, 0);
  EXPECT_LE(MaxSpeed(s), 0.5 + 1e-12);
  EXPECT_EQ(s.diagnostics.speed_capped, 1);
}

TEST_F(FabricStepperTest, CgIterationLimitIsReported) {
  FabricState s = MakeRestState(model_);
  StepOptions o;
  o.cg_max_iterations = 1;
  o.cg_tolerance = 1e-12;
  FabricStepper dut(model_, o);
  SetPointLoad(7, Eigen::Vector3d(0, 0, 1.0), &s);
  const StepResult r = dut.Step(&s);
  EXPECT_EQ(r.status, StepStatus::kCgNotConverged);
  EXPECT_EQ(s.diagnostics.cg_not_converged, 1);
  EXPECT_EQ(r.cg.iterations, 1);
}

}  // namespace
}  // namespace haptex::textile
