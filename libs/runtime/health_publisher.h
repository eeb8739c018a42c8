#pragma once
// Sends a service's Health to the launcher (or any peer) at a fixed rate from inside its loop,
// without allocating.

#include <cstdint>

#include "libs/net/messenger.h"
#include "libs/runtime/health_reporter.h"

namespace haptex::runtime {

class HealthPublisher final {
 public:
  /// Throws std::invalid_argument unless 0 < rate_hz <= 1000.
  HealthPublisher(HealthReporter* reporter, net::Messenger* messenger, net::Messenger::PeerId peer, double rate_hz,
                  std::int64_t start_ns);

  /// Sends Health when one period has passed since the last one. Returns true when it sent.
  bool MaybePublish(std::int64_t now_ns);
  /// True when MaybePublish(now_ns) would send.
  bool Due(std::int64_t now_ns) const { return now_ns >= next_ns_; }
  std::uint64_t published() const { return published_; }

 private:
  HealthReporter* reporter_;
  net::Messenger* messenger_;
  net::Messenger::PeerId peer_;
  std::int64_t period_ns_;
  std::int64_t start_ns_;
  std::int64_t next_ns_;
  std::uint64_t published_ = 0;
};

}  // namespace haptex::runtime
