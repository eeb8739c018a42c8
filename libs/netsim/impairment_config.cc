#include "libs/netsim/impairment_config.h"

#include <stdexcept>
#include <string>

#include "libs/netsim/parameter_check.h"

namespace haptex::netsim {

std::string_view JitterDistributionName(JitterDistribution distribution) {
  switch (distribution) {
    case JitterDistribution::kUniform:
      return "uniform";
    case JitterDistribution::kNormal:
      return "normal";
  }
  return "unknown";
}

JitterDistribution ParseJitterDistribution(std::string_view name) {
  if (name == "uniform") return JitterDistribution::kUniform;
  if (name == "normal") return JitterDistribution::kNormal;
  throw std::invalid_argument("jitter distribution must be 'uniform' or 'normal', got '" + std::string(name) + "'");
}

void Validate(const ImpairmentConfig& config) {
  using C = ImpairmentConfig;
  CheckRange("delay_ms", config.delay_ms, 0.0, C::kMaxDelay_ms);
  CheckRange("jitter_ms", config.jitter_ms, 0.0, C::kMaxDelay_ms);
  if (config.jitter_distribution != JitterDistribution::kUniform &&
      config.jitter_distribution != JitterDistribution::kNormal) {
    throw std::invalid_argument("jitter_distribution is not a known distribution");
  }
  CheckProbability("loss", config.loss);
  ValidateGilbertElliott(config.burst, "burst.");
  CheckProbability("duplicate", config.duplicate);
  CheckProbability("reorder", config.reorder);
  CheckRange("reorder_delay_ms", config.reorder_delay_ms, 0.0, C::kMaxDelay_ms);
  CheckRange("rate_kbps", config.rate_kbps, 0.0, C::kMaxRate_kbps);
  CheckWholeNumber("queue_bytes", static_cast<double>(config.queue_bytes), 1.0,
                   static_cast<double>(C::kMaxQueue_bytes));
  CheckRange("outage_after_s", config.outage_after_s, 0.0, C::kMaxOutage_s);
  CheckRange("outage_s", config.outage_s, 0.0, C::kMaxOutage_s);
  CheckWholeNumber("max_datagram_bytes", static_cast<double>(config.max_datagram_bytes), 1.0,
                   static_cast<double>(C::kMaxDatagram_bytes));
}

}  // namespace haptex::netsim
