#include "services/viewer/foxglove_messages.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <exception>
#include <limits>

namespace haptex::viewer {
namespace {

using nlohmann::json;

constexpr std::string_view kBase64Alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

void AppendLittleEndian(std::string& out, std::uint64_t value, int bytes) {
  for (int i = 0; i < bytes; ++i) out.push_back(static_cast<char>((value >> (8 * i)) & 0xffU));
}

std::uint64_t ReadLittleEndian(std::string_view in, int bytes) {
  std::uint64_t value = 0;
  for (int i = 0; i < bytes; ++i) value |= std::uint64_t{static_cast<unsigned char>(in[i])} << (8 * i);
  return value;
}

std::optional<std::uint32_t> AsUint32(const json& value) {
  if (!value.is_number_integer()) return std::nullopt;
  if (value.is_number_unsigned()) {
    const auto number = value.get<std::uint64_t>();
    if (number > std::numeric_limits<std::uint32_t>::max()) return std::nullopt;
    return static_cast<std::uint32_t>(number);
  }
  const auto number = value.get<std::int64_t>();
  if (number < 0 || number > std::int64_t{std::numeric_limits<std::uint32_t>::max()}) return std::nullopt;
  return static_cast<std::uint32_t>(number);
}

std::optional<std::uint32_t> Uint32Field(const json& object, const char* name) {
  const auto field = object.find(name);
  if (field == object.end()) return std::nullopt;
  return AsUint32(*field);
}

ClientRequest ParseSubscribe(const json& message) {
  const auto list = message.find("subscriptions");
  if (list == message.end() || !list->is_array()) return BadClientMessage{"subscribe without a subscriptions array"};
  SubscribeRequest request;
  for (const json& entry : *list) {
    if (!entry.is_object()) return BadClientMessage{"subscribe: a subscription is not an object"};
    const auto id = Uint32Field(entry, "id");
    const auto channel_id = Uint32Field(entry, "channelId");
    if (!id || !channel_id) return BadClientMessage{"subscribe: id and channelId must be uint32"};
    request.subscriptions.push_back({*id, *channel_id});
  }
  return request;
}

ClientRequest ParseUnsubscribe(const json& message) {
  const auto list = message.find("subscriptionIds");
  if (list == message.end() || !list->is_array()) {
    return BadClientMessage{"unsubscribe without a subscriptionIds array"};
  }
  UnsubscribeRequest request;
  for (const json& entry : *list) {
    const auto id = AsUint32(entry);
    if (!id) return BadClientMessage{"unsubscribe: subscription ids must be uint32"};
    request.subscription_ids.push_back(*id);
  }
  return request;
}

}  // namespace

std::string ServerInfoJson(std::string_view name, std::string_view session_id) {
  const json message = {{"op", "serverInfo"},
                        {"name", name},
                        {"capabilities", json::array()},
                        {"supportedEncodings", {"protobuf"}},
                        {"metadata", json::object()},
                        {"sessionId", session_id}};
  return message.dump(-1, ' ', false, json::error_handler_t::replace);
}

std::string AdvertiseJson(const std::vector<AdvertisedChannel>& channels) {
  json list = json::array();
  for (const AdvertisedChannel& advertised : channels) {
    list.push_back({{"id", advertised.id},
                    {"topic", advertised.channel.topic},
                    {"encoding", "protobuf"},
                    {"schemaName", advertised.channel.schema_name},
                    {"schema", Base64Encode(advertised.channel.schema_data)},
                    {"schemaEncoding", "protobuf"}});
  }
  const json message = {{"op", "advertise"}, {"channels", std::move(list)}};
  // A topic that is not UTF-8 must not make dump() throw: its bad bytes become U+FFFD.
  return message.dump(-1, ' ', false, json::error_handler_t::replace);
}

std::string StatusJson(StatusLevel level, std::string_view message) {
  const json status = {{"op", "status"}, {"level", static_cast<int>(level)}, {"message", message}};
  return status.dump(-1, ' ', false, json::error_handler_t::replace);
}

std::string MessageDataHeader(std::uint32_t subscription_id, std::uint64_t log_time_ns) {
  std::string header;
  header.reserve(kMessageDataHeaderBytes);
  header.push_back(static_cast<char>(kMessageDataOpcode));
  AppendLittleEndian(header, subscription_id, 4);
  AppendLittleEndian(header, log_time_ns, 8);
  return header;
}

std::string MessageDataFrame(std::uint32_t subscription_id, std::uint64_t log_time_ns, std::string_view payload) {
  std::string frame = MessageDataHeader(subscription_id, log_time_ns);
  frame.append(payload);
  return frame;
}

std::optional<MessageData> ParseMessageDataFrame(std::string_view frame) {
  if (frame.size() < kMessageDataHeaderBytes || static_cast<std::uint8_t>(frame[0]) != kMessageDataOpcode) {
    return std::nullopt;
  }
  MessageData data;
  data.subscription_id = static_cast<std::uint32_t>(ReadLittleEndian(frame.substr(1), 4));
  data.log_time_ns = ReadLittleEndian(frame.substr(5), 8);
  data.payload = frame.substr(kMessageDataHeaderBytes);
  return data;
}

ClientRequest ParseClientRequest(std::string_view text) {
  const json message = json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (message.is_discarded()) return BadClientMessage{"not JSON"};
  if (!message.is_object()) return BadClientMessage{"not a JSON object"};
  const auto op = message.find("op");
  if (op == message.end() || !op->is_string()) return BadClientMessage{"no op"};
  const auto& name = op->get_ref<const std::string&>();
  try {
    if (name == "subscribe") return ParseSubscribe(message);
    if (name == "unsubscribe") return ParseUnsubscribe(message);
  } catch (const std::exception& error) {
    return BadClientMessage{std::string("malformed ") + name + ": " + error.what()};
  }
  return BadClientMessage{"unsupported op '" + name.substr(0, 64) + "'"};
}

std::string Base64Encode(std::string_view bytes) {
  std::string text;
  text.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::size_t n = std::min<std::size_t>(3, bytes.size() - i);
    std::uint32_t group = 0;
    for (std::size_t k = 0; k < 3; ++k) {
      group = (group << 8) | (k < n ? static_cast<unsigned char>(bytes[i + k]) : 0U);
    }
    for (std::size_t k = 0; k < 4; ++k) {
      text.push_back(k <= n ? kBase64Alphabet[(group >> (18 - 6 * k)) & 0x3fU] : '=');
    }
  }
  return text;
}

std::optional<std::string> Base64Decode(std::string_view text) {
  if (text.size() % 4 != 0) return std::nullopt;
  std::string bytes;
  bytes.reserve(text.size() / 4 * 3);
  for (std::size_t i = 0; i < text.size(); i += 4) {
    const bool last = i + 4 == text.size();
    std::uint32_t group = 0;
    int padding = 0;
    for (std::size_t k = 0; k < 4; ++k) {
      const char c = text[i + k];
      std::uint32_t value = 0;
      if (c == '=' && last && k >= 2) {
        ++padding;
      } else {
        const std::size_t found = kBase64Alphabet.find(c);
        if (found == std::string_view::npos || padding > 0) return std::nullopt;
        value = static_cast<std::uint32_t>(found);
      }
      group = (group << 6) | value;
    }
    // Canonical: the bits that padding hides are zero.
    if ((padding == 1 && (group & 0xffU) != 0) || (padding == 2 && (group & 0xffffU) != 0)) return std::nullopt;
    for (int k = 0; k < 3 - padding; ++k) bytes.push_back(static_cast<char>((group >> (16 - 8 * k)) & 0xffU));
  }
  return bytes;
}

}  // namespace haptex::viewer
