#include "cli/relay_report.h"

#include <cstdio>
#include <sstream>

#include "launch/json_writer.h"
#include "libs/netsim/drop_cause.h"

namespace haptex::cli {
namespace {

constexpr double kMsPerNs = 1e-6;

netsim::DropCause CauseAt(std::size_t i) { return static_cast<netsim::DropCause>(i); }

void WriteConfig(const netsim::ImpairmentConfig& config, launch::JsonWriter* json) {
  json->BeginObject("config")
      .Field("delay_ms", config.delay_ms)
      .Field("jitter_ms", config.jitter_ms)
      .Field("jitter_dist", netsim::JitterDistributionName(config.jitter_distribution))
      .Field("loss", config.loss)
      .BeginObject("burst_loss")
      .Field("p", config.burst.p_good_to_bad)
      .Field("r", config.burst.p_bad_to_good)
      .Field("loss_bad", config.burst.loss_bad)
      .Field("loss_good", config.burst.loss_good)
      .EndObject()
      .Field("duplicate", config.duplicate)
      .Field("reorder", config.reorder)
      .Field("reorder_delay_ms", config.reorder_delay_ms)
      .Field("rate_kbps", config.rate_kbps)
      .Field("outage_after_s", config.outage_after_s)
      .Field("outage_s", config.outage_s)
      .Field("queue_bytes", std::uint64_t{config.queue_bytes})
      .Field("max_datagram_bytes", std::uint64_t{config.max_datagram_bytes})
      .EndObject();
}

void WriteDirection(std::string_view key, const RelayDirectionReport& direction, launch::JsonWriter* json) {
  const netsim::ImpairmentStats& stats = direction.stats;
  json->BeginObject(key);
  WriteConfig(direction.config, json);
  json->Field("seed", direction.seed)
      .Field("received", stats.received)
      .Field("forwarded", stats.forwarded)
      .Field("duplicated", stats.duplicated)
      .Field("held_back", stats.held_back)
      .Field("reordered", stats.reordered)
      .Field("dropped_total", stats.dropped.Total())
      .BeginObject("dropped");
  for (std::size_t i = 0; i < netsim::kDropCauseCount; ++i) {
    json->Field(netsim::DropCauseName(CauseAt(i)), stats.dropped.Get(CauseAt(i)));
  }
  json->EndObject()
      .Field("in_flight", stats.in_flight())
      .Field("outage_from_steady_ns", stats.outage_from_ns)
      .BeginObject("delay_ms")
      .Field("p50", stats.delay.Quantile_ns(0.50) * kMsPerNs)
      .Field("p99", stats.delay.Quantile_ns(0.99) * kMsPerNs)
      .Field("max", static_cast<double>(stats.delay.max_ns()) * kMsPerNs)
      .Field("mean", stats.delay.mean_ns() * kMsPerNs)
      .EndObject()
      .EndObject();
}

std::string Ms(double ns) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.3f", ns * kMsPerNs);
  return text;
}

void DirectionLine(std::string_view name, const RelayDirectionReport& direction, std::ostream& out) {
  const netsim::ImpairmentStats& stats = direction.stats;
  out << name << ": received " << stats.received << ", forwarded " << stats.forwarded << ", duplicated "
      << stats.duplicated << ", reordered " << stats.reordered << " (held back " << stats.held_back << "), dropped "
      << stats.dropped.Total();
  const char* separator = " (";
  for (std::size_t i = 0; i < netsim::kDropCauseCount; ++i) {
    if (stats.dropped.Get(CauseAt(i)) == 0) continue;
    out << separator << netsim::DropCauseName(CauseAt(i)) << " " << stats.dropped.Get(CauseAt(i));
    separator = ", ";
  }
  if (stats.dropped.Total() != 0) out << ")";
  out << "; delay ms p50 " << Ms(stats.delay.Quantile_ns(0.50)) << " p99 " << Ms(stats.delay.Quantile_ns(0.99))
      << " max " << Ms(static_cast<double>(stats.delay.max_ns())) << "\n";
}

}  // namespace

std::string RelayReportToText(const RelayReport& report) {
  std::ostringstream out;
  out.precision(3);
  out << std::fixed << "relay ran " << report.duration_s << " s: listen " << report.listen << ", upstream "
      << report.upstream << ", to " << report.to << ", back to "
      << (report.back_to.empty() ? "the last client" : report.back_to) << "\n";
  DirectionLine("forward", report.forward, out);
  DirectionLine("back", report.back, out);
  return out.str();
}

std::string RelayReportToJson(const RelayReport& report) {
  launch::JsonWriter json;
  json.BeginObject()
      .Field("listen", report.listen)
      .Field("upstream", report.upstream)
      .Field("to", report.to)
      .Field("back_to", report.back_to.empty() ? std::string_view("last client") : report.back_to)
      .Field("duration_s", report.duration_s);
  WriteDirection("forward", report.forward, &json);
  WriteDirection("back", report.back, &json);
  json.EndObject();
  return json.str();
}

}  // namespace haptex::cli
