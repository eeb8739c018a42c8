#include "services/viewer/foxglove_sink.h"

namespace haptex::viewer {

void FoxgloveSink::Publish(std::string_view topic, const google::protobuf::Message& message,
                           std::uint64_t log_time_ns) {
  const Channel* channel = nullptr;
  for (const Channel& c : channels_) {
    if (c.topic == topic) channel = &c;
  }
  if (channel == nullptr) {
    const auto* type = message.GetDescriptor();
    const std::uint32_t id =
        server_->AddChannel({std::string(topic), std::string(type->full_name()), codec::FileDescriptorSetOf(type)});
    channels_.push_back({std::string(topic), id});
    channel = &channels_.back();
  }
  if (!server_->HasSubscribers(channel->id)) return;
  message.SerializeToString(&buffer_);  // reuses the buffer's capacity
  server_->Publish(channel->id, log_time_ns, buffer_);
}

}  // namespace haptex::viewer
