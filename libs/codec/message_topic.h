#pragma once
// The topic a message goes under wherever it is shown or recorded (the viewer's channels, a run's
// MCAP file): its sender and its Envelope body field, "/global_sim/cloth_frame".

#include <string>
#include <string_view>

namespace haptex::codec {

inline std::string MessageTopic(std::string_view sender, std::string_view body_field_name) {
  return "/" + std::string(sender) + "/" + std::string(body_field_name);
}

}  // namespace haptex::codec
