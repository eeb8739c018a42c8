// run.mcap: a channel per service and body, schemas any reader can decode with, counts for
// summary.json, and the recordings back from it (trace export); a foreign MCAP is refused.
#include "launch/run_mcap.h"

#include <gmock/gmock.h>
#include <google/protobuf/descriptor.h>
#include <google/protobuf/descriptor.pb.h>
#include <google/protobuf/dynamic_message.h>
#include <gtest/gtest.h>

#include <fstream>

#include "libs/mcap/mcap_reader.h"
#include "libs/mcap/mcap_writer.h"
#include "tests/launch/launch_test_support.h"

namespace haptex::launch {
namespace {

using ::testing::HasSubstr;
namespace pb = google::protobuf;

v1::Envelope At(std::int64_t t_ns, const std::string& sender, std::uint64_t sequence) {
  v1::Envelope e;
  e.set_send_time_ns(t_ns);
  e.set_sender(sender);
  e.set_sequence(sequence);
  return e;
}

// two services, four body types, sent interleaved in time; one envelope without a body
std::vector<Recording> TwoServices() {
  Recording bridge, local;
  for (int i = 0; i < 5; ++i) {
    v1::Envelope states = At(1000 + 100 * i, "device_bridge", i + 1);
    states.mutable_finger_states()->set_controller_sequence(7 + i);
    bridge.envelopes.push_back(states);
    v1::Envelope model = At(1050 + 100 * i, "local_contact", 2 * i + 1);
    model.mutable_force_model()->add_fingers()->set_contact_state(v1::CONTACT_STATE_V);
    local.envelopes.push_back(model);
    v1::Envelope trace = At(1060 + 100 * i, "local_contact", 2 * i + 2);
    trace.mutable_touch_trace()->add_fingers()->set_normal_force_n(0.5 * i);
    local.envelopes.push_back(trace);
  }
  v1::Envelope health = At(900, "device_bridge", 99);
  health.mutable_health()->add_loops()->set_name("device_bridge");
  bridge.envelopes.push_back(health);
  bridge.envelopes.push_back(At(950, "device_bridge", 100));  // no body
  return {bridge, local};
}

TEST(LaunchRunMcapTest, OneChannelPerServiceAndBodyWithProtobufSchemas) {
  RunMcapCounts counts;
  const mcap::McapFile file = mcap::ReadMcap(MakeRunMcap(TwoServices(), &counts));
  EXPECT_EQ(counts.messages, 16u);
  EXPECT_EQ(counts.without_body, 1u);
  EXPECT_EQ(counts.channels, (std::map<std::string, std::uint64_t>{{"/device_bridge/finger_states", 5},
                                                                   {"/device_bridge/health", 1},
                                                                   {"/local_contact/force_model", 5},
                                                                   {"/local_contact/touch_trace", 5}}));
  ASSERT_EQ(file.channels.size(), 4u);
  ASSERT_TRUE(file.statistics.has_value());
  EXPECT_EQ(file.statistics->message_count, 16u);
  for (const mcap::Channel& c : file.channels) {
    EXPECT_EQ(c.message_encoding, "protobuf");
    const mcap::Schema* schema = file.FindSchema(c.schema_id);
    ASSERT_NE(schema, nullptr);
    EXPECT_EQ(schema->encoding, "protobuf");
    EXPECT_EQ(file.statistics->channel_message_counts.at(c.id), counts.channels.at(c.topic));
  }
  std::map<std::string, std::string> type_of;
  for (const mcap::Channel& c : file.channels) type_of[c.topic] = file.FindSchema(c.schema_id)->name;
  EXPECT_EQ(type_of["/device_bridge/finger_states"], "haptex.v1.FingerStates");
  EXPECT_EQ(type_of["/local_contact/force_model"], "haptex.v1.ForceModel");
  EXPECT_EQ(type_of["/device_bridge/health"], "haptex.v1.Health");

  // messages in send-time order, log time the send time, payload the body (not the Envelope)
  ASSERT_EQ(file.messages.size(), 16u);
  EXPECT_EQ(file.messages.front().log_time, 900u);
  EXPECT_EQ(file.messages[1].log_time, 1000u);
  EXPECT_EQ(file.messages[1].publish_time, 1000u);
  EXPECT_EQ(file.messages[1].sequence, 1u);
  v1::FingerStates states;
  ASSERT_TRUE(states.ParseFromString(file.messages[1].data));
  EXPECT_EQ(states.controller_sequence(), 7u);
}

// What an independent reader does: build the types from the schema's FileDescriptorSet alone
// (no compiled-in haptex types) and decode every message with them.
TEST(LaunchRunMcapTest, EverySchemaDecodesItsMessagesOnItsOwn) {
  const mcap::McapFile file = mcap::ReadMcap(MakeRunMcap(TwoServices(), nullptr));
  for (const mcap::Channel& c : file.channels) {
    const mcap::Schema* schema = file.FindSchema(c.schema_id);
    pb::FileDescriptorSet set;
    ASSERT_TRUE(set.ParseFromString(schema->data)) << c.topic;
    pb::DescriptorPool pool;
    for (const pb::FileDescriptorProto& f : set.file()) ASSERT_NE(pool.BuildFile(f), nullptr) << f.name();
    const pb::Descriptor* type = pool.FindMessageTypeByName(schema->name);
    ASSERT_NE(type, nullptr) << schema->name;
    pb::DynamicMessageFactory factory(&pool);
    for (const mcap::Message& m : file.messages) {
      if (m.channel_id != c.id) continue;
      std::unique_ptr<pb::Message> decoded(factory.GetPrototype(type)->New());
      EXPECT_TRUE(decoded->ParseFromString(m.data)) << c.topic;
      EXPECT_TRUE(decoded->GetReflection()->GetUnknownFields(*decoded).empty()) << c.topic;
    }
  }
}

TEST(LaunchRunMcapTest, RecordingsComeBackFromTheFile) {
  const std::string dir = testing::FreshDir("run_mcap");
  const RunMcapCounts counts = WriteRunMcap(TwoServices(), dir + "/run.mcap");
  EXPECT_EQ(counts.file, "run.mcap");
  const auto recordings = RecordingsFromMcap(dir + "/run.mcap");
  ASSERT_EQ(recordings.size(), 2u);
  EXPECT_THAT(recordings[0].path, HasSubstr("/device_bridge/*"));
  ASSERT_EQ(recordings[0].envelopes.size(), 6u);  // the one without a body is not in run.mcap
  EXPECT_EQ(recordings[0].envelopes[0].sender(), "device_bridge");
  EXPECT_EQ(recordings[0].envelopes[0].send_time_ns(), 900);
  EXPECT_TRUE(recordings[0].envelopes[0].has_health());
  EXPECT_EQ(recordings[0].envelopes[1].finger_states().controller_sequence(), 7u);
  EXPECT_EQ(recordings[0].envelopes[1].sequence(), 1u);
  ASSERT_EQ(recordings[1].envelopes.size(), 10u);
  EXPECT_EQ(recordings[1].envelopes[1].touch_trace().fingers(0).normal_force_n(), 0.0);
  EXPECT_EQ(recordings[1].envelopes[9].touch_trace().fingers(0).normal_force_n(), 2.0);
}

std::string ErrorOf(const std::string& path) {
  try {
    RecordingsFromMcap(path);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(LaunchRunMcapTest, MissingCutAndForeignFilesAreClearErrors) {
  const std::string dir = testing::FreshDir("run_mcap_bad");
  EXPECT_THAT(ErrorOf(dir + "/missing.mcap"), HasSubstr("cannot read"));

  const std::string bytes = MakeRunMcap(TwoServices(), nullptr);
  std::ofstream(dir + "/cut.mcap", std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  EXPECT_THAT(ErrorOf(dir + "/cut.mcap"), HasSubstr("cut.mcap: cut short"));

  auto foreign = [&](const std::string& name, const std::string& topic, const std::string& schema_name) {
    std::ofstream out(dir + "/" + name, std::ios::binary);
    mcap::McapWriter w(out);
    const auto s = w.AddSchema(schema_name, "protobuf", "");
    const auto c = w.AddChannel(s, topic, "protobuf");
    w.AddMessage({c, 0, 1, 1, ""});
    w.Finish();
    out.close();
    return ErrorOf(dir + "/" + name);
  };
  EXPECT_THAT(foreign("a.mcap", "/camera/image", "sensor_msgs.Image"), HasSubstr("not a haptex run's MCAP"));
  EXPECT_THAT(foreign("b.mcap", "no_slash", "haptex.v1.Health"), HasSubstr("not /<service>/<body>"));
  EXPECT_THAT(foreign("c.mcap", "/tactile/health", "haptex.v1.PinFrame"), HasSubstr("schema is not haptex.v1.Health"));
}

}  // namespace
}  // namespace haptex::launch
