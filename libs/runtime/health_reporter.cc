#include "libs/runtime/health_reporter.h"

#include <unistd.h>

namespace haptex::runtime {

HealthReporter::HealthReporter(std::string service) {
  health_.set_service(std::move(service));
  health_.set_pid(static_cast<std::uint32_t>(getpid()));
}

void HealthReporter::AddLoop(const LoopStats* loop) {
  loops_.push_back(loop);
  health_.add_loops();
}

void HealthReporter::AddLatency(std::string name, const LatencyHistogram* histogram) {
  AddLatency(std::move(name), [histogram] {
    return LatencySummary{histogram->count(), histogram->Percentile(0.50) * 1e-3, histogram->Percentile(0.99) * 1e-3,
                          static_cast<double>(histogram->max_ns()) * 1e-3};
  });
}

void HealthReporter::AddLatency(std::string name, LatencySource source) {
  latencies_.push_back(std::move(source));
  health_.add_latencies()->set_name(std::move(name));
}

HealthReporter::CounterId HealthReporter::AddCounter(std::string name) {
  health_.add_counters()->set_name(std::move(name));
  counter_values_.push_back(0);
  return counter_values_.size() - 1;
}

const v1::Health& HealthReporter::Build(double uptime_s) {
  health_.set_state(state_);
  health_.set_uptime_s(uptime_s);
  for (std::size_t i = 0; i < loops_.size(); ++i) {
    loops_[i]->FillProto(health_.mutable_loops(static_cast<int>(i)));
  }
  for (std::size_t i = 0; i < latencies_.size(); ++i) {
    v1::LatencyStats* out = health_.mutable_latencies(static_cast<int>(i));
    const LatencySummary summary = latencies_[i]();
    out->set_samples(summary.samples);
    out->set_p50_us(summary.p50_us);
    out->set_p99_us(summary.p99_us);
    out->set_max_us(summary.max_us);
  }
  for (std::size_t i = 0; i < counter_values_.size(); ++i) {
    health_.mutable_counters(static_cast<int>(i))->set_value(counter_values_[i]);
  }
  return health_;
}

}  // namespace haptex::runtime
