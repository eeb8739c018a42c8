#pragma once
// Why a datagram (or a copy of one) never left the relay.

#include <array>
#include <cstddef>
#include <cstdint>
#include <string_view>

namespace haptex::netsim {

enum class DropCause : std::uint8_t {
  kLoss,           // independent (Bernoulli) loss
  kBurstLoss,      // Gilbert-Elliott loss
  kQueueOverflow,  // the rate limiter's queue (bytes) or the relay's buffers (datagrams) were full
  kOversize,       // larger than max_datagram_bytes
  kSendFailed,     // the kernel refused to send it (relay runtime)
  kNoDestination,  // nobody to send it to yet: no client seen (relay runtime)
  kUnsentAtStop,   // still held when the relay stopped (relay runtime)
  kOutage,         // arrived while the link was dead (ImpairmentConfig::outage_s)
};

inline constexpr std::size_t kDropCauseCount = 8;

/// snake_case name, as in reports: "loss", "burst_loss", ...
std::string_view DropCauseName(DropCause cause);

/// One counter per cause.
class DropCounts {
 public:
  void Add(DropCause cause) { ++counts_[static_cast<std::size_t>(cause)]; }
  std::uint64_t Get(DropCause cause) const { return counts_[static_cast<std::size_t>(cause)]; }
  std::uint64_t Total() const;

 private:
  std::array<std::uint64_t, kDropCauseCount> counts_{};
};

}  // namespace haptex::netsim
