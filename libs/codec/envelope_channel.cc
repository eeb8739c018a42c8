#include "libs/codec/envelope_channel.h"

#include <stdexcept>

#include "haptex/v1/envelope.pb.h"

namespace haptex::codec {

const google::protobuf::OneofDescriptor& EnvelopeBodyOneof() {
  const google::protobuf::OneofDescriptor* body = v1::Envelope::descriptor()->FindOneofByName("body");
  if (body == nullptr) throw std::logic_error("haptex.v1.Envelope has no oneof body");
  return *body;
}

EnvelopeChannel EnvelopeChannelOf(std::string_view topic, std::string_view message_encoding,
                                  std::string_view schema_name, std::string_view schema_encoding, std::string* why) {
  const auto refuse = [&](const std::string& reason) {
    if (why != nullptr) *why = reason;
    return EnvelopeChannel{};
  };
  const auto slash = topic.find('/', 1);
  if (topic.empty() || topic[0] != '/' || slash == std::string_view::npos || slash == 1) {
    return refuse("the topic is not /<service>/<body>");
  }
  EnvelopeChannel channel{std::string(topic.substr(1, slash - 1)), nullptr};
  const std::string_view body = topic.substr(slash + 1);
  const google::protobuf::OneofDescriptor& oneof = EnvelopeBodyOneof();
  for (int i = 0; i < oneof.field_count(); ++i) {
    if (oneof.field(i)->name() == body) channel.body = oneof.field(i);
  }
  if (channel.body == nullptr) return refuse("\"" + std::string(body) + "\" is no Envelope body");
  if (message_encoding != kChannelEncoding) return refuse("message encoding " + std::string(message_encoding));
  const std::string& type = channel.body->message_type()->full_name();
  if (schema_encoding != kChannelEncoding || schema_name != type) return refuse("its schema is not " + type);
  return channel;
}

}  // namespace haptex::codec
