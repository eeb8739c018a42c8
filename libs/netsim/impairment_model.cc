#include "libs/netsim/impairment_model.h"

#include <algorithm>
#include <cmath>

namespace haptex::netsim {
namespace {

// one stream per kind of draw (RandomStream explains why)
enum Stream : std::uint64_t {
  kLossStream = 1,
  kBurstLossStream,
  kBurstStateStream,
  kDuplicateStream,
  kJitterStream,
  kReorderStream,
};

std::int64_t ToNs(double ms) { return std::llround(ms * 1e6); }

const ImpairmentConfig& Validated(const ImpairmentConfig& config) {
  Validate(config);
  return config;
}

}  // namespace

ImpairmentModel::ImpairmentModel(const ImpairmentConfig& config, std::uint64_t seed)
    : config_(Validated(config)),
      delay_ns_(ToNs(config.delay_ms)),
      reorder_delay_ns_(ToNs(config.reorder_delay_ms)),
      outage_from_ns_(ToNs(config.outage_after_s * 1e3)),
      outage_ns_(ToNs(config.outage_s * 1e3)),
      burst_(config.burst),
      loss_draws_(seed, kLossStream),
      burst_loss_draws_(seed, kBurstLossStream),
      burst_state_draws_(seed, kBurstStateStream),
      duplicate_draws_(seed, kDuplicateStream),
      jitter_draws_(seed, kJitterStream),
      reorder_draws_(seed, kReorderStream) {}

Decision ImpairmentModel::Decide(std::int64_t arrival_ns, std::size_t size_bytes, std::size_t free_buffers) {
  Decision decision;
  decision.sequence = next_sequence_++;
  decision.arrival_ns = std::max(arrival_ns, last_arrival_ns_);
  last_arrival_ns_ = decision.arrival_ns;
  ++stats_.received;

  // Every datagram takes one draw from each stream, whatever happens to it, so the n-th
  // datagram's loss does not depend on the sizes or fates of those before it.
  const bool lost = loss_draws_.Uniform01() < config_.loss;
  const double u_burst_loss = burst_loss_draws_.Uniform01();
  const bool burst_lost = burst_.Step(u_burst_loss, burst_state_draws_.Uniform01());
  const bool duplicated = duplicate_draws_.Uniform01() < config_.duplicate;

  if (first_arrival_ns_ == std::numeric_limits<std::int64_t>::min()) {
    first_arrival_ns_ = decision.arrival_ns;
    if (config_.outage_s > 0.0) stats_.outage_from_ns = first_arrival_ns_ + outage_from_ns_;
  }
  if (config_.outage_s > 0.0 && decision.arrival_ns >= first_arrival_ns_ + outage_from_ns_ &&
      decision.arrival_ns < first_arrival_ns_ + outage_from_ns_ + outage_ns_) {
    stats_.dropped.Add(DropCause::kOutage);
    return decision;
  }
  if (size_bytes > config_.max_datagram_bytes) {
    stats_.dropped.Add(DropCause::kOversize);
    return decision;
  }
  if (lost) {
    stats_.dropped.Add(DropCause::kLoss);
    return decision;
  }
  if (burst_lost) {
    stats_.dropped.Add(DropCause::kBurstLoss);
    return decision;
  }

  const int wanted = duplicated ? 2 : 1;
  if (duplicated) ++stats_.duplicated;
  for (int copy = 0; copy < wanted; ++copy) {
    std::int64_t departure_ns = decision.arrival_ns;
    if (free_buffers == 0 || !PassRateLimit(decision.arrival_ns, size_bytes, &departure_ns)) {
      stats_.dropped.Add(DropCause::kQueueOverflow);
      continue;
    }
    --free_buffers;
    std::int64_t release_ns = departure_ns + delay_ns_ + DrawJitter_ns();
    if (reorder_draws_.Uniform01() < config_.reorder) {
      release_ns += reorder_delay_ns_;
      ++stats_.held_back;
    }
    decision.release_ns[static_cast<std::size_t>(decision.copies++)] = release_ns;
  }
  return decision;
}

bool ImpairmentModel::PassRateLimit(std::int64_t arrival_ns, std::size_t size_bytes, std::int64_t* departure_ns) {
  if (config_.rate_kbps <= 0.0) return true;
  const std::int64_t start_ns = std::max(arrival_ns, link_free_ns_);
  // bytes of earlier datagrams not yet serialised when this one arrives
  const double backlog_bytes = static_cast<double>(start_ns - arrival_ns) * config_.rate_kbps / 8e6;
  if (backlog_bytes + static_cast<double>(size_bytes) > static_cast<double>(config_.queue_bytes)) {
    return false;
  }
  // rounded up, so consecutive departures are never closer than size * 8 / rate
  const auto serialisation_ns =
      static_cast<std::int64_t>(std::ceil(static_cast<double>(size_bytes) * 8e6 / config_.rate_kbps));
  link_free_ns_ = start_ns + serialisation_ns;
  *departure_ns = link_free_ns_;
  return true;
}

std::int64_t ImpairmentModel::DrawJitter_ns() {
  if (config_.jitter_ms <= 0.0) return 0;
  // truncation: draw again while the total delay would be negative; the bound only matters for
  // a delay far below the jitter, where each draw still succeeds with probability near 1/2
  constexpr int kMaxDraws = 64;
  double jitter_ms = 0.0;
  for (int draw = 0; draw < kMaxDraws; ++draw) {
    jitter_ms = config_.jitter_distribution == JitterDistribution::kNormal
                    ? config_.jitter_ms * jitter_draws_.StandardNormal()
                    : config_.jitter_ms * (2.0 * jitter_draws_.Uniform01() - 1.0);
    if (config_.delay_ms + jitter_ms >= 0.0) break;
  }
  return std::max(ToNs(jitter_ms), -delay_ns_);
}

void ImpairmentModel::OnDelivered(std::uint64_t sequence, std::int64_t arrival_ns, std::int64_t sent_ns) {
  ++stats_.forwarded;
  if (delivered_any_ && sequence < highest_delivered_) {
    ++stats_.reordered;
  } else {
    highest_delivered_ = sequence;
    delivered_any_ = true;
  }
  stats_.delay.Record(sent_ns - arrival_ns);
}

void ImpairmentModel::OnUndelivered(DropCause cause) { stats_.dropped.Add(cause); }

}  // namespace haptex::netsim
