#include "libs/device/finger_state_estimator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace haptex::device {
namespace {

constexpr double kQuantum_m = 0.032e-3;
constexpr std::uint64_t kTick_ns = 200000;  // 5 kHz
constexpr double kTick_s = 2e-4;

Eigen::Vector3d Quantise(const Eigen::Vector3d& p) { return (p / kQuantum_m).array().round() * kQuantum_m; }

TEST(FingerStateEstimatorTest, ConstantVelocityThroughQuantisation) {
  FingerStateEstimator dut(FingerStateEstimatorConfig{});
  FingerState state;
  const Eigen::Vector3d v(0.1, -0.05, 0.02);
  for (int k = 0; k < 2000; ++k) {
    dut.Update(Quantise(v * k * kTick_s), Eigen::Quaterniond::Identity(), k * kTick_ns, &state);
  }
  EXPECT_TRUE(state.valid);
  EXPECT_LT((state.v_W_m_per_s - v).norm(), 0.01);
}

// Scripted motion with a peak speed of 0.3 m/s (a sinusoid along a diagonal), quantised to
// 0.032 mm at 5 kHz: predicting 2 ms ahead at least halves the error of using the last sample.
TEST(FingerStateEstimatorTest, PredictionHalvesTheErrorTwoMillisecondsAhead) {
  FingerStateEstimatorConfig config;
  config.prediction_horizon_s = 0.002;
  FingerStateEstimator dut(config);
  FingerState state;

  const double amplitude_m = 0.03;
  const double w = 0.3 / amplitude_m;  // peak speed 0.3 m/s
  const Eigen::Vector3d dir = Eigen::Vector3d(1.0, 0.5, -0.3).normalized();
  auto truth = [&](double t) { return Eigen::Vector3d(dir * amplitude_m * std::sin(w * t)); };

  double sum_sq_predicted = 0.0;
  double sum_sq_held = 0.0;
  for (int k = 0; k < 5 * 5000; ++k) {  // 5 s
    const double t = k * kTick_s;
    dut.Update(Quantise(truth(t)), Eigen::Quaterniond::Identity(), k * kTick_ns, &state);
    if (t < 0.1) continue;  // filter warm-up
    const Eigen::Vector3d future = truth(t + 0.002);
    sum_sq_predicted += (state.p_pred_W_m - future).squaredNorm();
    sum_sq_held += (state.p_W_m - future).squaredNorm();
  }
  const double ratio = std::sqrt(sum_sq_predicted / sum_sq_held);
  EXPECT_LT(ratio, 0.5) << "prediction error / no-prediction error";
  // reported with --gtest_output=xml
  RecordProperty("rms_error_predicted_um", std::to_string(std::sqrt(sum_sq_predicted / 24500) * 1e6));
  RecordProperty("rms_error_held_um", std::to_string(std::sqrt(sum_sq_held / 24500) * 1e6));
  RecordProperty("error_ratio", std::to_string(ratio));
}

TEST(FingerStateEstimatorTest, PredictsOrientationFromAngularVelocity) {
  FingerStateEstimatorConfig config;
  config.prediction_horizon_s = 0.002;
  FingerStateEstimator dut(config);
  FingerState state;
  const Eigen::Vector3d axis = Eigen::Vector3d(0.2, 1.0, 0.1).normalized();
  const double rate = 2.0;  // rad/s
  for (int k = 0; k < 1000; ++k) {
    const Eigen::Quaterniond q(Eigen::AngleAxisd(rate * k * kTick_s, axis));
    dut.Update(Eigen::Vector3d::Zero(), q, k * kTick_ns, &state);
  }
  EXPECT_LT((state.w_W_rad_per_s - rate * axis).norm(), 1e-3);
  const Eigen::Quaterniond expected(Eigen::AngleAxisd(rate * (999 * kTick_s + 0.002), axis));
  EXPECT_LT(state.q_pred_WF.angularDistance(expected), 1e-5);
}

TEST(FingerStateEstimatorTest, LongGapRestartsVelocity) {
  FingerStateEstimator dut(FingerStateEstimatorConfig{});
  FingerState state;
  for (int k = 0; k < 500; ++k) {
    dut.Update(Eigen::Vector3d(0.2 * k * kTick_s, 0, 0), Eigen::Quaterniond::Identity(), k * kTick_ns, &state);
  }
  ASSERT_GT(state.v_W_m_per_s.x(), 0.1);
  // 100 ms later, far away: no 1 m/s spike, the estimate restarts from rest
  dut.Update(Eigen::Vector3d(0.12, 0, 0), Eigen::Quaterniond::Identity(), 600 * kTick_ns, &state);
  EXPECT_EQ(state.v_W_m_per_s, Eigen::Vector3d::Zero());
  EXPECT_EQ(state.p_pred_W_m, state.p_W_m);
}

TEST(FingerStateEstimatorTest, RepeatedTimestampKeepsVelocity) {
  FingerStateEstimator dut(FingerStateEstimatorConfig{});
  FingerState state;
  for (int k = 0; k < 500; ++k) {
    dut.Update(Eigen::Vector3d(0.2 * k * kTick_s, 0, 0), Eigen::Quaterniond::Identity(), k * kTick_ns, &state);
  }
  const Eigen::Vector3d v = state.v_W_m_per_s;
  dut.Update(state.p_W_m, Eigen::Quaterniond::Identity(), 499 * kTick_ns, &state);
  EXPECT_EQ(state.v_W_m_per_s, v);
}

TEST(FingerStateEstimatorTest, InvalidConfigThrowsWithTheFieldName) {
  FingerStateEstimatorConfig config;
  config.velocity_cutoff_Hz = 0.0;
  try {
    FingerStateEstimator dut(config);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("velocity_cutoff_Hz"), std::string::npos) << e.what();
  }
  config = FingerStateEstimatorConfig{};
  config.prediction_horizon_s = -0.001;
  EXPECT_THROW(FingerStateEstimator{config}, std::invalid_argument);
}

}  // namespace
}  // namespace haptex::device

namespace haptex::device {
namespace {

TEST(FingerStateEstimatorHorizonTest, SetPredictionHorizonIsClampedAndIgnoresNan) {
  FingerStateEstimator estimator{FingerStateEstimatorConfig{}};
  estimator.SetPredictionHorizon(0.0004);
  EXPECT_DOUBLE_EQ(estimator.config().prediction_horizon_s, 0.0004);
  estimator.SetPredictionHorizon(5.0);
  EXPECT_DOUBLE_EQ(estimator.config().prediction_horizon_s, 0.1);
  estimator.SetPredictionHorizon(std::nan(""));
  EXPECT_DOUBLE_EQ(estimator.config().prediction_horizon_s, 0.1);
  estimator.SetPredictionHorizon(-1.0);
  EXPECT_DOUBLE_EQ(estimator.config().prediction_horizon_s, 0.0);
}

}  // namespace
}  // namespace haptex::device
