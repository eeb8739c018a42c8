#pragma once
// The frames of the Foxglove WebSocket protocol v1 (subprotocol foxglove.websocket.v1) that the
// server sends and the client requests it understands. Server messages are JSON text frames, except
// message data: a binary frame of opcode 0x01, uint32 subscription id, uint64 log time [ns] and the
// payload, integers little-endian.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "services/viewer/foxglove_channel.h"

namespace haptex::viewer {

inline constexpr std::string_view kFoxgloveSubprotocol = "foxglove.websocket.v1";
inline constexpr std::uint8_t kMessageDataOpcode = 0x01;
inline constexpr std::size_t kMessageDataHeaderBytes = 1 + 4 + 8;

struct AdvertisedChannel {
  std::uint32_t id = 0;
  FoxgloveChannel channel;
};

enum class StatusLevel { kInfo = 0, kWarning = 1, kError = 2 };

/// {"op":"serverInfo",...}: no optional capabilities, protobuf the only encoding.
std::string ServerInfoJson(std::string_view name, std::string_view session_id);
/// {"op":"advertise","channels":[...]}: every channel protobuf, its schema base64.
std::string AdvertiseJson(const std::vector<AdvertisedChannel>& channels);
/// {"op":"status",...}: tells a client why a request of its was ignored.
std::string StatusJson(StatusLevel level, std::string_view message);

/// The header of a message data frame; the payload follows it.
std::string MessageDataHeader(std::uint32_t subscription_id, std::uint64_t log_time_ns);
std::string MessageDataFrame(std::uint32_t subscription_id, std::uint64_t log_time_ns, std::string_view payload);

struct MessageData {
  std::uint32_t subscription_id = 0;
  std::uint64_t log_time_ns = 0;
  std::string_view payload;  // a view into the frame
};
/// The client side of a message data frame; nullopt for a frame too short or of another opcode.
std::optional<MessageData> ParseMessageDataFrame(std::string_view frame);

struct Subscription {
  std::uint32_t id = 0;
  std::uint32_t channel_id = 0;
};
struct SubscribeRequest {
  std::vector<Subscription> subscriptions;
};
struct UnsubscribeRequest {
  std::vector<std::uint32_t> subscription_ids;
};
struct BadClientMessage {
  std::string reason;
};
using ClientRequest = std::variant<SubscribeRequest, UnsubscribeRequest, BadClientMessage>;

/// A client's JSON text frame. Anything but a well-formed subscribe or unsubscribe (bad JSON, an
/// unknown op, a missing or mistyped field, an id beyond uint32) is a BadClientMessage.
ClientRequest ParseClientRequest(std::string_view text);

std::string Base64Encode(std::string_view bytes);
/// nullopt for anything but canonical, padded base64.
std::optional<std::string> Base64Decode(std::string_view text);

}  // namespace haptex::viewer
