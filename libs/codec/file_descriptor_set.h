#pragma once
// The schema of a protobuf message type as it travels with the messages (Foxglove's channels, an
// MCAP file's schema records): the message's .proto file and every file it imports, so that a
// reader can build the type from nothing else.

#include <string>

namespace google::protobuf {
class Descriptor;
}

namespace haptex::codec {

/// The serialized FileDescriptorSet of a message type: its file and every file it imports,
/// dependencies first.
std::string FileDescriptorSetOf(const google::protobuf::Descriptor* type);

}  // namespace haptex::codec
