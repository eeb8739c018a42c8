#include "libs/net/messenger.h"

#include "libs/net/udp_address.h"

namespace haptex::net {
namespace {

SenderIdentity WithEpoch(SenderIdentity identity) {
  if (identity.epoch == 0) identity.epoch = WallClockNs();
  return identity;
}

}  // namespace

std::uint64_t WallClockNs() {
  return static_cast<std::uint64_t>(
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch())
          .count());
}

Messenger::Messenger(const SessionKey& key, MessengerConfig config)
    : endpoint_(config.bind_address),
      sealer_(key, WithEpoch(config.identity)),
      opener_(key, config.identity.session_id, config.max_datagram_bytes),
      // no larger than what peers with the same limit accept: a bigger message fails to seal
      // (counted as send_failed) instead of being dropped as oversized at the other end
      send_buffer_(config.max_datagram_bytes),
      receive_buffer_(config.max_datagram_bytes),
      arena_block_(config.arena_bytes) {
  google::protobuf::ArenaOptions options;
  options.initial_block = arena_block_.data();
  options.initial_block_size = arena_block_.size();
  arena_ = std::make_unique<google::protobuf::Arena>(options);
  std::vector<std::string> names{config.identity.name};
  names.insert(names.end(), config.also_known_as.begin(), config.also_known_as.end());
  opener_.AcceptDestinations(std::move(names));
}

Messenger::PeerId Messenger::AddPeer(std::string_view name, std::string_view address) {
  return AddPeer(name, ResolveUdpAddress(address));
}

Messenger::PeerId Messenger::AddPeer(std::string_view name, const Endpoint& endpoint) {
  peers_.push_back(Peer{std::string(name), endpoint});
  return peers_.size() - 1;
}

bool Messenger::Transmit(std::size_t bytes, const Endpoint& to) {
  if (bytes == 0 || !endpoint_.SendTo(std::span<const std::uint8_t>(send_buffer_.data(), bytes), to)) {
    ++send_failures_;
    return false;
  }
  ++sent_;
  last_sent_bytes_ = bytes;
  return true;
}

Messenger::Received Messenger::ReceiveOne(Endpoint* from, const v1::Envelope** envelope) {
  const auto bytes = endpoint_.ReceiveOne(receive_buffer_, from);
  if (!bytes) return Received::kNothingWaiting;
  if (*bytes > receive_buffer_.size()) {
    opener_.CountDrop(DropReason::kOversized);
    return Received::kDropped;
  }
  arena_->Reset();
  auto* parsed = google::protobuf::Arena::CreateMessage<v1::Envelope>(arena_.get());
  const DropReason reason = opener_.Open(std::span<const std::uint8_t>(receive_buffer_.data(), *bytes), parsed);
  if (reason != DropReason::kNone) return Received::kDropped;
  *envelope = parsed;
  return Received::kAccepted;
}

bool NewestWins::Accept(const v1::Envelope& envelope) {
  if (envelope.sender_epoch() < epoch_) return false;
  if (envelope.sender_epoch() == epoch_ && envelope.sequence() <= sequence_) return false;
  epoch_ = envelope.sender_epoch();
  sequence_ = envelope.sequence();
  return true;
}

}  // namespace haptex::net
