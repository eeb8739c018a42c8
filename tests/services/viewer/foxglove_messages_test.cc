#include "services/viewer/foxglove_messages.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <string>
#include <variant>

namespace haptex::viewer {
namespace {

using nlohmann::json;

TEST(MessageDataFrameTest, IsOpcodeThenLittleEndianIdAndTimeThenPayload) {
  const std::string frame = MessageDataFrame(0x04030201U, 0x0c0b0a0908070605ULL, "abc");
  const std::string expected(
      "\x01\x01\x02\x03\x04\x05\x06\x07\x08\x09\x0a\x0b\x0c"
      "abc",
      16);
  EXPECT_EQ(frame, expected);
  EXPECT_EQ(MessageDataHeader(0x04030201U, 0x0c0b0a0908070605ULL), expected.substr(0, kMessageDataHeaderBytes));
}

TEST(MessageDataFrameTest, ParsesBackAndRefusesShortOrForeignFrames) {
  const std::string payload("\x00\xff payload", 10);
  const std::string frame = MessageDataFrame(7, 1'700'000'000'123'456'789ULL, payload);
  const auto parsed = ParseMessageDataFrame(frame);
  ASSERT_TRUE(parsed);
  EXPECT_EQ(parsed->subscription_id, 7U);
  EXPECT_EQ(parsed->log_time_ns, 1'700'000'000'123'456'789ULL);
  EXPECT_EQ(parsed->payload, payload);
  EXPECT_TRUE(ParseMessageDataFrame(MessageDataFrame(1, 2, "")));
  EXPECT_FALSE(ParseMessageDataFrame(frame.substr(0, kMessageDataHeaderBytes - 1)));
  std::string time_frame = frame;
  time_frame[0] = 0x02;
  EXPECT_FALSE(ParseMessageDataFrame(time_frame));
}

TEST(ServerInfoJsonTest, NamesTheServerAndProtobuf) {
  const json info = json::parse(ServerInfoJson("haptex", "session-1"));
  EXPECT_EQ(info["op"], "serverInfo");
  EXPECT_EQ(info["name"], "haptex");
  EXPECT_EQ(info["capabilities"], json::array());
  EXPECT_EQ(info["supportedEncodings"], json::array({"protobuf"}));
  EXPECT_TRUE(info["metadata"].is_object());
  EXPECT_EQ(info["sessionId"], "session-1");
}

TEST(AdvertiseJsonTest, ListsEveryChannelWithItsSchemaInBase64) {
  const std::string schema("\x0a\x05hello\x00\xff", 9);
  const json advertise = json::parse(
      AdvertiseJson({{3, {"/cloth", "haptex.v1.ClothFrame", schema}}, {4, {"/scene", "foxglove.SceneUpdate", "xyz"}}}));
  EXPECT_EQ(advertise["op"], "advertise");
  ASSERT_EQ(advertise["channels"].size(), 2U);
  const json& cloth = advertise["channels"][0];
  EXPECT_EQ(cloth["id"], 3);
  EXPECT_EQ(cloth["topic"], "/cloth");
  EXPECT_EQ(cloth["encoding"], "protobuf");
  EXPECT_EQ(cloth["schemaName"], "haptex.v1.ClothFrame");
  EXPECT_EQ(cloth["schemaEncoding"], "protobuf");
  EXPECT_EQ(Base64Decode(cloth["schema"].get<std::string>()), schema);
  EXPECT_EQ(advertise["channels"][1]["schema"], "eHl6");
}

TEST(AdvertiseJsonTest, SurvivesATopicThatIsNotUtf8) {
  const json advertise = json::parse(AdvertiseJson({{1, {std::string("/bad\xff", 5), "t", ""}}}));
  EXPECT_EQ(advertise["channels"][0]["topic"], "/bad\xef\xbf\xbd");
}

TEST(StatusJsonTest, CarriesLevelAndMessage) {
  const json status = json::parse(StatusJson(StatusLevel::kWarning, "unknown channel 9"));
  EXPECT_EQ(status["op"], "status");
  EXPECT_EQ(status["level"], 1);
  EXPECT_EQ(status["message"], "unknown channel 9");
}

TEST(ParseClientRequestTest, ReadsSubscribeAndUnsubscribe) {
  const ClientRequest subscribe = ParseClientRequest(
      R"({"op":"subscribe","subscriptions":[{"id":0,"channelId":1},{"id":4294967295,"channelId":2}]})");
  ASSERT_TRUE(std::holds_alternative<SubscribeRequest>(subscribe));
  const auto& subscriptions = std::get<SubscribeRequest>(subscribe).subscriptions;
  ASSERT_EQ(subscriptions.size(), 2U);
  EXPECT_EQ(subscriptions[0].id, 0U);
  EXPECT_EQ(subscriptions[0].channel_id, 1U);
  EXPECT_EQ(subscriptions[1].id, 4294967295U);

  const ClientRequest unsubscribe = ParseClientRequest(R"({"op":"unsubscribe","subscriptionIds":[0, 5]})");
  ASSERT_TRUE(std::holds_alternative<UnsubscribeRequest>(unsubscribe));
  EXPECT_EQ(std::get<UnsubscribeRequest>(unsubscribe).subscription_ids, (std::vector<std::uint32_t>{0, 5}));
}

TEST(ParseClientRequestTest, AnythingElseIsBad) {
  for (const char* text : {
           "",
           "not json",
           "{\"op\":\"subscribe\"",
           "[1,2]",
           "42",
           "{}",
           R"({"op":7})",
           R"({"op":"advertise","channels":[]})",
           R"({"op":"getParameters","parameterNames":[]})",
           R"({"op":"subscribe"})",
           R"({"op":"subscribe","subscriptions":{}})",
           R"({"op":"subscribe","subscriptions":[1]})",
           R"({"op":"subscribe","subscriptions":[{"id":1}]})",
           R"({"op":"subscribe","subscriptions":[{"id":-1,"channelId":1}]})",
           R"({"op":"subscribe","subscriptions":[{"id":4294967296,"channelId":1}]})",
           R"({"op":"subscribe","subscriptions":[{"id":1.5,"channelId":1}]})",
           R"({"op":"subscribe","subscriptions":[{"id":"1","channelId":1}]})",
           R"({"op":"unsubscribe","subscriptionIds":["a"]})",
           R"({"op":"unsubscribe"})",
       }) {
    const ClientRequest request = ParseClientRequest(text);
    ASSERT_TRUE(std::holds_alternative<BadClientMessage>(request)) << text;
    EXPECT_FALSE(std::get<BadClientMessage>(request).reason.empty()) << text;
  }
}

TEST(Base64Test, EncodesTheStandardVectors) {
  EXPECT_EQ(Base64Encode(""), "");
  EXPECT_EQ(Base64Encode("f"), "Zg==");
  EXPECT_EQ(Base64Encode("fo"), "Zm8=");
  EXPECT_EQ(Base64Encode("foo"), "Zm9v");
  EXPECT_EQ(Base64Encode("foob"), "Zm9vYg==");
  EXPECT_EQ(Base64Encode("fooba"), "Zm9vYmE=");
  EXPECT_EQ(Base64Encode("foobar"), "Zm9vYmFy");
  EXPECT_EQ(Base64Encode(std::string("\xfb\xff\x00", 3)), "+/8A");
}

TEST(Base64Test, DecodesWhatItEncodesAndRefusesTheRest) {
  std::string every_byte;
  for (int i = 0; i < 256; ++i) every_byte.push_back(static_cast<char>(i));
  for (std::size_t n = 0; n < every_byte.size(); n += 37) {
    EXPECT_EQ(Base64Decode(Base64Encode(every_byte.substr(0, n))), every_byte.substr(0, n));
  }
  EXPECT_FALSE(Base64Decode("Zg="));
  EXPECT_FALSE(Base64Decode("Z==="));
  EXPECT_FALSE(Base64Decode("Zh=="));  // non-zero bits under the padding
  EXPECT_FALSE(Base64Decode("Zg==Zg=="));
  EXPECT_FALSE(Base64Decode("Zm9v!A=="));
  EXPECT_FALSE(Base64Decode("Z=9v"));
}

}  // namespace
}  // namespace haptex::viewer
