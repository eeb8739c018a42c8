#pragma once
// A topic that the Foxglove server advertises: its messages are protobuf of one type, whose
// schema travels with the advertisement so that any client can decode them.

#include <string>

namespace haptex::viewer {

struct FoxgloveChannel {
  std::string topic;        // e.g. "/cloth"
  std::string schema_name;  // the message's full name, e.g. "foxglove.SceneUpdate"
  std::string schema_data;  // a serialized google.protobuf.FileDescriptorSet (codec::FileDescriptorSetOf)
};

}  // namespace haptex::viewer
