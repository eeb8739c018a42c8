// haptex trace export: one CSV per body type, times from the earliest message.
#include "launch/trace_export.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "tests/launch/launch_test_support.h"

namespace haptex::launch {
namespace {

using ::testing::HasSubstr;

v1::Envelope At(std::int64_t t_ns, const std::string& sender) {
  v1::Envelope e;
  e.set_send_time_ns(t_ns);
  e.set_sender(sender);
  return e;
}

TEST(LaunchTraceExportTest, OneFilePerBodyType) {
  Recording local;
  v1::Envelope model = At(2'000'000'000, "local_contact");
  auto* f = model.mutable_force_model()->add_fingers();
  f->set_finger(v1::FINGER_INDEX);
  f->mutable_f0_w_n()->set_x(3);
  f->mutable_f0_w_n()->set_y(4);
  f->set_contact_state(v1::CONTACT_STATE_V);
  local.envelopes.push_back(model);
  v1::Envelope trace = At(2'500'000'000, "local_contact");
  auto* touch = trace.mutable_touch_trace()->add_fingers();
  touch->set_finger(v1::FINGER_THUMB);
  touch->set_normal_force_n(1.5);
  local.envelopes.push_back(trace);
  Recording bridge;
  v1::Envelope health = At(1'000'000'000, "device_bridge");
  health.mutable_health()->add_loops()->set_name("device_bridge");
  health.mutable_health()->add_counters()->set_name("status_frames_accepted");
  bridge.envelopes.push_back(health);

  const std::string dir = testing::FreshDir("trace_export");
  const auto rows = ExportCsv({local, bridge}, dir);
  EXPECT_EQ(rows.at("force_model.csv"), 1u);
  EXPECT_EQ(rows.at("touch_trace.csv"), 1u);
  EXPECT_EQ(rows.at("health.csv"), 1u);
  EXPECT_EQ(rows.at("health_counters.csv"), 1u);
  EXPECT_EQ(rows.count("pin_frame.csv"), 0u);
  const std::string csv = testing::ReadText(dir + "/force_model.csv");
  EXPECT_THAT(csv, HasSubstr("t_s,sender,finger,f0_x_n"));
  EXPECT_THAT(csv, HasSubstr("\n1,local_contact,index,3,4,0,5,"));  // 1 s after the earliest; |F0| = 5
  EXPECT_THAT(testing::ReadText(dir + "/touch_trace.csv"), HasSubstr("\n1.5,local_contact,thumb,0,"));
  EXPECT_THAT(testing::ReadText(dir + "/health.csv"), HasSubstr("\n0,device_bridge,STATE_UNSPECIFIED,"));
}

TEST(LaunchTraceExportTest, FingerNames) {
  EXPECT_EQ(FingerName(v1::FINGER_THUMB), "thumb");
  EXPECT_EQ(FingerName(v1::FINGER_INDEX), "index");
}

}  // namespace
}  // namespace haptex::launch
