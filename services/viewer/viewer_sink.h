#pragma once
// Where the viewer's loop puts what it shows: the Foxglove WebSocket server in the service
// (foxglove_sink.h), a capture in tests. One topic per sending service and message type
// ("/global_sim/cloth_frame"), as in the run's MCAP recording, so a page or Foxglove reads a live
// session and a recording alike.

#include <cstdint>
#include <string_view>

#include <google/protobuf/message.h>

namespace haptex::viewer {

class ViewerSink {
 public:
  virtual ~ViewerSink() = default;
  /// `log_time_ns`: nanoseconds since the Unix epoch, as Foxglove shows them.
  virtual void Publish(std::string_view topic, const google::protobuf::Message& message, std::uint64_t log_time_ns) = 0;
};

}  // namespace haptex::viewer
