#pragma once
// The schema of a protobuf message type as Foxglove wants it: the message's .proto file and every
// file it imports, so that a client can build the type from nothing else.

#include <string>

namespace google::protobuf {
class Descriptor;
}

namespace haptex::viewer {

/// The serialized FileDescriptorSet of a message type: its file and every file it imports,
/// dependencies first.
std::string FileDescriptorSetOf(const google::protobuf::Descriptor* type);

}  // namespace haptex::viewer
