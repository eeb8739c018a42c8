#pragma once
// What a channel of a haptex recording or live session is: "/<service>/<body>" carrying one Envelope
// body type, protobuf-encoded, its schema named by the body's full type name. One check for every
// reader of a run's MCAP file, so that each refuses a file that is not a haptex run's alike.

#include <string>
#include <string_view>

#include <google/protobuf/descriptor.h>

namespace haptex::codec {

/// Message and schema encoding of every haptex channel.
inline constexpr std::string_view kChannelEncoding = "protobuf";

/// A channel's sender and the Envelope body field it carries.
struct EnvelopeChannel {
  std::string sender;
  const google::protobuf::FieldDescriptor* body = nullptr;
};

/// The channel's sender and body; nullptr body and `*why` (may be null) set when the channel is not
/// a haptex one: the topic is not "/<service>/<body>", <body> is no Envelope body, or an encoding or
/// the schema's name is not the body's.
EnvelopeChannel EnvelopeChannelOf(std::string_view topic, std::string_view message_encoding,
                                  std::string_view schema_name, std::string_view schema_encoding, std::string* why);

/// The Envelope's oneof of bodies.
const google::protobuf::OneofDescriptor& EnvelopeBodyOneof();

}  // namespace haptex::codec
