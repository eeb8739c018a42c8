// The resume proxy alone (libs/device/resume_proxy.h): the force held, the proxy on the surface,
// the return within the bound, the end of a contact, and a late model's cap.
#include "libs/device/resume_proxy.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace haptex::device {
namespace {

constexpr double kTick_s = 2e-4;

// A finger pressing +x into a surface at x = 0 with `force_N` pushing it back (-x), for `seconds`.
void Hold(ResumeProxy& proxy, double force_N, double seconds) {
  const Eigen::Vector3d p(0.0, 0.0, 0.0), F(-force_N, 0.0, 0.0);
  for (int k = 0; k < static_cast<int>(std::lround(seconds / kTick_s)); ++k) {
    proxy.BeginTick(false, kTick_s);
    proxy.EndTick(proxy.Shape(F, p, Eigen::Vector3d::Zero()), p, true, kTick_s);
  }
}

TEST(ResumeProxyTest, TheHeldForceIsTheMeanOfTheLastHundredMilliseconds) {
  HeldForceWindow window;
  for (int k = 0; k < 1000; ++k) window.Add(1.0, kTick_s, 0.1);  // 0.2 s at 1 N
  for (int k = 0; k < 500; ++k) window.Add(3.0, kTick_s, 0.1);   // 0.1 s at 3 N
  EXPECT_NEAR(window.Mean(), 3.0, 0.11);
  window.Clear();
  EXPECT_EQ(window.Mean(), 0.0);
}

TEST(ResumeProxyTest, AFingerThatPassedTheSurfaceIsRenderedOnItAndPushedBackWithinTheBound) {
  ResumeProxy proxy(ResumeProxyConfig{}, 0.1);
  Hold(proxy, 2.0, 0.2);
  // the cut: 10 ms without force, the finger falls 4 mm into the surface
  const Eigen::Vector3d deep(0.004, 0.001, 0.0);
  EXPECT_TRUE(proxy.BeginTick(true, kTick_s));
  EXPECT_EQ(proxy.phase(), ResumeProxy::Phase::kCut);
  EXPECT_NEAR(proxy.held_N(), 2.0, 1e-9);
  for (int k = 0; k < 50; ++k) proxy.BeginTick(true, kTick_s);
  // the contact models see the proxy on the surface, moved along it but not into it
  EXPECT_TRUE(proxy.Constrain(deep).isApprox(Eigen::Vector3d(0.0, 0.001, 0.0)));
  // back: the model at the proxy plus the return spring, within max(1.1 x 2, 2 + 0.3) = 2.3 N
  proxy.BeginTick(false, kTick_s);
  EXPECT_EQ(proxy.phase(), ResumeProxy::Phase::kResuming);
  const Eigen::Vector3d F = proxy.Shape(Eigen::Vector3d(-2.0, 0.0, 0.0), deep, Eigen::Vector3d::Zero());
  EXPECT_NEAR(F.norm(), 2.3, 1e-9);
  EXPECT_LT(F.x(), 0.0) << "pushes the finger out";
  EXPECT_TRUE(proxy.limited_since_cut());
  // never pulls, however fast the finger comes out
  const Eigen::Vector3d out =
      proxy.Shape(Eigen::Vector3d(-0.1, 0.0, 0.0), Eigen::Vector3d(0.0005, 0.0, 0.0), Eigen::Vector3d(-5.0, 0.0, 0.0));
  EXPECT_LE(out.x(), 0.0);
  // back on the surface: the proxy is the finger again, the bound still holds for the watch
  proxy.Shape(Eigen::Vector3d(-2.0, 0.0, 0.0), Eigen::Vector3d(0.0001, 0.0, 0.0), Eigen::Vector3d::Zero());
  EXPECT_FALSE(proxy.constraining());
  EXPECT_NEAR(
      proxy.Shape(Eigen::Vector3d(-9.0, 0.0, 0.0), Eigen::Vector3d(0.0001, 0.0, 0.0), Eigen::Vector3d::Zero()).norm(),
      2.3, 1e-9);
  // until the finger has been back for settle_s
  for (int k = 0; k < 501; ++k) proxy.BeginTick(false, kTick_s);
  EXPECT_EQ(proxy.phase(), ResumeProxy::Phase::kFollowing);
  EXPECT_NEAR(proxy.Shape(Eigen::Vector3d(-9.0, 0.0, 0.0), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()).norm(),
              9.0, 1e-9);
}

TEST(ResumeProxyTest, AFingerThatLeftTheContactEndsTheResume) {
  ResumeProxy proxy(ResumeProxyConfig{}, 0.1);
  Hold(proxy, 2.0, 0.2);
  proxy.BeginTick(true, kTick_s);
  proxy.BeginTick(false, kTick_s);
  // the user let go: outside the surface, and the model gives nothing there
  proxy.Shape(Eigen::Vector3d::Zero(), Eigen::Vector3d(-0.003, 0.0, 0.0), Eigen::Vector3d::Zero());
  EXPECT_EQ(proxy.phase(), ResumeProxy::Phase::kFollowing);
  EXPECT_EQ(proxy.contacts_ended(), 0u);
}

// A user squeezing harder than the bound: the finger stays 5 mm past the surface. The bound
// holds flat for watch_s after the cut, cuts again within it do not start it anew, and then it
// rises at release_rate_N_per_s with the proxy still on the surface: no step in the force.
TEST(ResumeProxyTest, ABoundOutlastedByTheSqueezeRisesAtItsRateFromTheFirstCut) {
  const ResumeProxyConfig config;
  ResumeProxy proxy(config, 0.1);
  Hold(proxy, 2.0, 0.2);
  const Eigen::Vector3d deep(0.005, 0.0, 0.0);
  const auto tick = [&](bool cut) {
    proxy.BeginTick(cut, kTick_s);
    const Eigen::Vector3d F = proxy.Shape(Eigen::Vector3d(-2.0, 0.0, 0.0), deep, Eigen::Vector3d::Zero());
    proxy.EndTick(cut ? Eigen::Vector3d::Zero() : F, deep, false, kTick_s);
    return F.norm();
  };
  double t_s = 0.0, before_N = 0.0;
  // a host that stalls again every 200 ms: 5 ms cuts
  while (t_s < config.watch_s - 1e-9) {
    const bool cut = std::fmod(t_s, 0.2) < 0.005;
    const double F = tick(cut);
    if (!cut) {
      EXPECT_NEAR(F, 2.3, 1e-9) << "flat at the bound at " << t_s << " s";
    }
    t_s += kTick_s;
  }
  EXPECT_TRUE(proxy.constraining());
  before_N = 2.3;
  for (int k = 0; k < 500; ++k) {  // 100 ms of release
    const double F = tick(false);
    EXPECT_LE(F - before_N, config.release_rate_N_per_s * kTick_s + 1e-9);
    EXPECT_GE(F, before_N - 1e-12);
    before_N = F;
    EXPECT_TRUE(proxy.constraining()) << "the proxy holds while the bound rises";
  }
  EXPECT_NEAR(before_N, 2.3 + 0.1 * config.release_rate_N_per_s, 0.02);
  // the resume's peak is the bound's: the release after its second is the squeeze's
  EXPECT_NEAR(proxy.peak_since_cut_N(), 2.3, 0.002);
  // the finger comes back to the surface: the proxy is the finger again, and settle_s later, free
  proxy.Shape(Eigen::Vector3d(-2.0, 0.0, 0.0), Eigen::Vector3d(0.0001, 0.0, 0.0), Eigen::Vector3d::Zero());
  EXPECT_FALSE(proxy.constraining());
  proxy.BeginTick(false, kTick_s);
  EXPECT_EQ(proxy.phase(), ResumeProxy::Phase::kFollowing);
}

// A finger that never comes back (a squeeze stronger than the device) is let go release_max_s
// after the watch.
TEST(ResumeProxyTest, TheProxyGivesUpAFingerThatNeverComesBack) {
  const ResumeProxyConfig config;
  ResumeProxy proxy(config, 0.1);
  Hold(proxy, 2.0, 0.2);
  proxy.BeginTick(true, kTick_s);
  const int ticks = static_cast<int>(std::lround((config.watch_s + config.release_max_s) / kTick_s));
  for (int k = 0; k < ticks + 1; ++k) {
    proxy.BeginTick(false, kTick_s);
    proxy.Shape(Eigen::Vector3d(-2.0, 0.0, 0.0), Eigen::Vector3d(0.02, 0.0, 0.0), Eigen::Vector3d::Zero());
  }
  EXPECT_EQ(proxy.phase(), ResumeProxy::Phase::kFollowing);
  EXPECT_FALSE(proxy.constraining());
}

TEST(ResumeProxyTest, ACutLongerThanTheResumeWindowEndsTheContact) {
  ResumeProxy proxy(ResumeProxyConfig{}, 0.1);
  Hold(proxy, 2.0, 0.2);
  EXPECT_TRUE(proxy.BeginTick(true, 0.15));  // a 150 ms stall of our own
  EXPECT_EQ(proxy.phase(), ResumeProxy::Phase::kFollowing);
  EXPECT_EQ(proxy.contacts_ended(), 1u);
  EXPECT_FALSE(proxy.constraining());
}

TEST(ResumeProxyTest, LateModelsAreNotCappedUnlessAsked) {
  ResumeProxy proxy(ResumeProxyConfig{}, 0.1);
  Hold(proxy, 2.0, 0.2);
  const Eigen::Vector3d big(-5.0, 0.0, 0.0);
  EXPECT_EQ(proxy.CapLateModel(big, 0.010, kTick_s), big);
}

TEST(ResumeProxyTest, NoHeldContactNothingToResume) {
  ResumeProxy proxy(ResumeProxyConfig{}, 0.1);
  Hold(proxy, 0.1, 0.2);  // below min_held_N
  EXPECT_FALSE(proxy.BeginTick(true, kTick_s));
  EXPECT_EQ(proxy.phase(), ResumeProxy::Phase::kFollowing);
}

TEST(ResumeProxyTest, ALateModelIsHeldToTheBoundUntilItsWatchIsOver) {
  ResumeProxyConfig config;
  config.cap_late_models = true;
  ResumeProxy proxy(config, 0.1);
  for (int k = 0; k < 100; ++k) proxy.OnModelArrival(0.001);
  Hold(proxy, 2.0, 0.2);
  const Eigen::Vector3d big(-5.0, 0.0, 0.0);
  EXPECT_EQ(proxy.CapLateModel(big, 0.001, kTick_s), big) << "a model of this link's rhythm is not late";
  EXPECT_NEAR(proxy.CapLateModel(big, 0.002, kTick_s).norm(), 2.3, 1e-9);
  // fresh again: the bound holds on for late_watch_s
  EXPECT_NEAR(proxy.CapLateModel(big, 0.0, kTick_s).norm(), 2.3, 1e-9);
  for (int k = 0; k < 500; ++k) proxy.CapLateModel(big, 0.0, kTick_s);
  EXPECT_EQ(proxy.CapLateModel(big, 0.0, kTick_s), big);
  EXPECT_GT(proxy.late_model_caps(), 0u);
  // a jittery link's 4 ms gaps are its rhythm, not lateness
  proxy.OnModelArrival(0.004);
  EXPECT_EQ(proxy.CapLateModel(big, 0.005, kTick_s), big);
}

TEST(ResumeProxyTest, RefusesABadConfig) {
  ResumeProxyConfig config;
  config.bound_ratio = 0.9;
  EXPECT_THROW(ResumeProxy(config, 0.1), std::invalid_argument);
  config = ResumeProxyConfig{};
  config.spring_N_per_m = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(ResumeProxy(config, 0.1), std::invalid_argument);
  config = ResumeProxyConfig{};
  config.release_rate_N_per_s = 0.0;  // a bound that never lets go
  EXPECT_THROW(ResumeProxy(config, 0.1), std::invalid_argument);
  EXPECT_THROW(ResumeProxy(ResumeProxyConfig{}, -1.0), std::invalid_argument);
}

}  // namespace
}  // namespace haptex::device
