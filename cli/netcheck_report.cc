#include "cli/netcheck_report.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "launch/json_writer.h"

namespace haptex::cli {
namespace {

double PercentileUs(const std::vector<std::int64_t>& sorted_ns, double q) {
  if (sorted_ns.empty()) return 0.0;
  const auto rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(sorted_ns.size())));
  return static_cast<double>(sorted_ns[std::clamp<std::size_t>(rank, 1, sorted_ns.size()) - 1]) * 1e-3;
}

}  // namespace

ProbeRecorder::ProbeRecorder(std::size_t capacity) : rtt_ns_(capacity, -1) {}

void ProbeRecorder::OnReply(std::uint64_t probe_sequence, std::int64_t rtt_ns) {
  if (probe_sequence == 0 || probe_sequence > rtt_ns_.size() || rtt_ns < 0) {
    ++rejected_;
    return;
  }
  std::int64_t& slot = rtt_ns_[probe_sequence - 1];
  if (slot >= 0) {
    ++duplicates_;
    return;
  }
  slot = rtt_ns;
  if (probe_sequence < highest_) ++reordered_;
  highest_ = std::max(highest_, probe_sequence);
}

void ProbeRecorder::Summarise(std::uint64_t sent, const LinkVerdictLimits& limits, NetcheckReport* report) const {
  std::vector<std::int64_t> answered;
  answered.reserve(rtt_ns_.size());
  double jitter_sum = 0;
  std::uint64_t jitter_pairs = 0;
  std::int64_t previous = -1;
  const std::size_t considered = std::min<std::size_t>(sent, rtt_ns_.size());
  for (std::size_t i = 0; i < considered; ++i) {
    const std::int64_t rtt = rtt_ns_[i];
    if (rtt < 0) continue;
    answered.push_back(rtt);
    if (previous >= 0) {
      jitter_sum += std::abs(static_cast<double>(rtt - previous));
      ++jitter_pairs;
    }
    previous = rtt;
  }
  report->sent = sent;
  report->received = answered.size();
  report->lost = sent - answered.size();
  report->duplicates = duplicates_;
  report->reordered = reordered_;
  report->rejected = rejected_;
  report->loss_fraction = sent ? static_cast<double>(report->lost) / static_cast<double>(sent) : 0.0;
  report->jitter_us = jitter_pairs ? jitter_sum / static_cast<double>(jitter_pairs) * 1e-3 : 0.0;
  std::sort(answered.begin(), answered.end());
  if (!answered.empty()) {
    double sum = 0;
    for (std::int64_t v : answered) sum += static_cast<double>(v);
    report->rtt_min_us = static_cast<double>(answered.front()) * 1e-3;
    report->rtt_max_us = static_cast<double>(answered.back()) * 1e-3;
    report->rtt_mean_us = sum / static_cast<double>(answered.size()) * 1e-3;
    report->rtt_p50_us = PercentileUs(answered, 0.50);
    report->rtt_p99_us = PercentileUs(answered, 0.99);
    report->rtt_p999_us = PercentileUs(answered, 0.999);
  }
  ClassifyLink(limits, report);
}

void ClassifyLink(const LinkVerdictLimits& limits, NetcheckReport* report) {
  if (report->received == 0) {
    report->verdict = "unreachable";
    report->advice =
        "no authenticated reply: check the address, that `haptex netcheck serve` runs "
        "there, firewalls, and that both ends use the same session key";
  } else if (report->rtt_p99_us <= limits.good_p99_us && report->loss_fraction <= limits.good_loss) {
    report->verdict = "good";
    report->advice = "any service may run on the far side, local_contact at 1 kHz included";
  } else if (report->rtt_p99_us <= limits.usable_p99_us && report->loss_fraction <= limits.usable_loss) {
    report->verdict = "usable";
    report->advice =
        "the simulation may run across this link (device_bridge here, local_contact and global_sim there: the "
        "bridge renders their delayed force models passively); or only global_sim (remote_global), which keeps the "
        "contact here but renders a finger pressing loose cloth stiffer the longer the round trip";
  } else if (report->rtt_p99_us <= limits.global_only_p99_us && report->loss_fraction <= limits.global_only_loss) {
    report->verdict = "global_only";
    report->advice =
        "too slow for the haptic link: keep device_bridge and local_contact here; only global_sim may run there "
        "(remote_global: the cloth far from the fingers moves late, a finger pressing loose cloth feels it stiffer)";
  } else {
    report->verdict = "poor";
    report->advice =
        "too slow or lossy for haptic use: run every service next to the device, and expect late cloth updates "
        "from anything on the far side";
  }
}

std::string ReportToJson(const NetcheckReport& r) {
  launch::JsonWriter json;
  json.BeginObject()
      .Field("target", r.target)
      .Field("rate_hz", r.rate_hz)
      .Field("seconds", r.seconds)
      .Field("datagram_bytes", r.datagram_bytes)
      .Field("sent", r.sent)
      .Field("received", r.received)
      .Field("lost", r.lost)
      .Field("loss_fraction", r.loss_fraction)
      .Field("duplicates", r.duplicates)
      .Field("reordered", r.reordered)
      .Field("rejected", r.rejected)
      .Field("send_failures", r.send_failures)
      .Field("send_overruns", r.send_overruns)
      .BeginObject("rtt_us")
      .Field("min", r.rtt_min_us)
      .Field("mean", r.rtt_mean_us)
      .Field("p50", r.rtt_p50_us)
      .Field("p99", r.rtt_p99_us)
      .Field("p99_9", r.rtt_p999_us)
      .Field("max", r.rtt_max_us)
      .EndObject()
      .Field("jitter_us", r.jitter_us)
      .Field("verdict", r.verdict)
      .Field("advice", r.advice)
      .EndObject();
  return json.str();
}

std::string ReportToText(const NetcheckReport& r) {
  std::ostringstream out;
  out.setf(std::ios::fixed);
  out.precision(1);
  out << "netcheck " << r.target << ": " << r.sent << " probes at " << r.rate_hz << " Hz for " << r.seconds << " s, "
      << r.datagram_bytes << " B datagrams\n"
      << "  round trip [us]  min " << r.rtt_min_us << "  p50 " << r.rtt_p50_us << "  p99 " << r.rtt_p99_us << "  p99.9 "
      << r.rtt_p999_us << "  max " << r.rtt_max_us << "\n"
      << "  jitter " << r.jitter_us << " us   lost " << r.lost << " (" << r.loss_fraction * 100.0 << " %)   reordered "
      << r.reordered << "   duplicates " << r.duplicates << "   rejected " << r.rejected << "   send overruns "
      << r.send_overruns << "\n"
      << "  verdict: " << r.verdict << ": " << r.advice << "\n";
  return out.str();
}

}  // namespace haptex::cli
