#include "libs/runtime/health_publisher.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace haptex::runtime {

HealthPublisher::HealthPublisher(HealthReporter* reporter, net::Messenger* messenger, net::Messenger::PeerId peer,
                                 double rate_hz, std::int64_t start_ns)
    : reporter_(reporter), messenger_(messenger), peer_(peer), start_ns_(start_ns), next_ns_(start_ns) {
  if (!(rate_hz > 0.0 && rate_hz <= 1000.0)) {
    throw std::invalid_argument("health rate must be in (0, 1000] Hz, got " + std::to_string(rate_hz));
  }
  period_ns_ = static_cast<std::int64_t>(std::llround(1e9 / rate_hz));
}

bool HealthPublisher::MaybePublish(std::int64_t now_ns) {
  if (now_ns < next_ns_) return false;
  // keep the cadence, but never send bursts after a stall
  next_ns_ += period_ns_;
  if (next_ns_ <= now_ns) next_ns_ = now_ns + period_ns_;
  const double uptime_s = static_cast<double>(now_ns - start_ns_) * 1e-9;
  if (!messenger_->Send(peer_, reporter_->Build(uptime_s))) return false;
  ++published_;
  return true;
}

}  // namespace haptex::runtime
