#pragma once
// The viewer's sink in the service: each topic becomes a Foxglove channel (its schema the message's
// FileDescriptorSet) the first time it is published; a message is serialized only when a client
// subscribes to its channel.

#include <cstdint>
#include <string>
#include <vector>

#include "services/viewer/foxglove_server.h"
#include "services/viewer/viewer_sink.h"

namespace haptex::viewer {

class FoxgloveSink final : public ViewerSink {
 public:
  explicit FoxgloveSink(FoxgloveServer* server) : server_(server) {}
  void Publish(std::string_view topic, const google::protobuf::Message& message, std::uint64_t log_time_ns) override;

 private:
  struct Channel {
    std::string topic;
    std::uint32_t id;
  };
  FoxgloveServer* server_;
  std::vector<Channel> channels_;
  std::string buffer_;
};

}  // namespace haptex::viewer
