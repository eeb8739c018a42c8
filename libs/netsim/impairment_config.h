#pragma once
// What one direction of a relay does to datagrams. Units are in the names; every probability is
// per datagram.

#include <cstddef>
#include <string_view>

#include "libs/netsim/gilbert_elliott.h"

namespace haptex::netsim {

enum class JitterDistribution {
  kUniform,  // uniform on [-jitter_ms, +jitter_ms]
  kNormal,   // normal with standard deviation jitter_ms
};

/// "uniform" / "normal".
std::string_view JitterDistributionName(JitterDistribution distribution);
/// Inverse of JitterDistributionName; throws std::invalid_argument listing the known names.
JitterDistribution ParseJitterDistribution(std::string_view name);

struct ImpairmentConfig {
  static constexpr double kMaxDelay_ms = 60'000.0;
  static constexpr double kMaxRate_kbps = 100'000'000.0;  // 100 Gbit/s
  static constexpr std::size_t kMaxQueue_bytes = std::size_t{1} << 30;
  static constexpr std::size_t kMaxDatagram_bytes = 65'535;
  static constexpr double kMaxOutage_s = 86'400.0;

  double delay_ms = 0.0;  // added to every datagram
  // Each datagram's delay moves by a draw from the distribution; draws that would make the
  // total delay negative are drawn again (truncation), so delay_ms + jitter never goes below 0.
  double jitter_ms = 0.0;
  JitterDistribution jitter_distribution = JitterDistribution::kUniform;
  double loss = 0.0;           // independent loss probability
  GilbertElliottConfig burst;  // burst loss, on top of `loss`
  double duplicate = 0.0;      // probability that a datagram is sent twice
  // Probability that a datagram is held back by reorder_delay_ms more, so later ones overtake it.
  double reorder = 0.0;
  double reorder_delay_ms = 10.0;
  // Serialisation at this rate (0: unlimited): a datagram leaves only after the previous one has
  // finished. Datagrams that would make the bytes waiting to be serialised exceed queue_bytes are
  // dropped as queue overflow.
  double rate_kbps = 0.0;
  std::size_t queue_bytes = 256 * 1024;
  std::size_t max_datagram_bytes = 65'507;  // larger ones are dropped as oversize
  // A dead link: every datagram arriving in [outage_after_s, outage_after_s + outage_s) after the
  // first one this direction saw is dropped (cause "outage"); 0 s: none.
  double outage_after_s = 0.0;
  double outage_s = 0.0;
};

/// Throws std::invalid_argument naming the first bad parameter (NaN, infinite, negative,
/// probabilities outside [0, 1], values beyond the limits above).
void Validate(const ImpairmentConfig& config);

}  // namespace haptex::netsim
