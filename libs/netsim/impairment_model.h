#pragma once
// The impairment model of one direction of a relay: for each datagram, given its arrival time,
// whether it is dropped and why, whether it is duplicated, and when each copy is released. Then
// what became of each copy (delivered when, or dropped later) comes back in, for the reordering
// count and the achieved delay. Pure: time is an argument; seeded; no allocation after
// construction.

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "libs/netsim/delay_histogram.h"
#include "libs/netsim/drop_cause.h"
#include "libs/netsim/gilbert_elliott.h"
#include "libs/netsim/impairment_config.h"
#include "libs/netsim/random_stream.h"

namespace haptex::netsim {

struct ImpairmentStats {
  std::uint64_t received = 0;    // datagrams offered
  std::uint64_t duplicated = 0;  // extra copies made (each then forwarded or dropped)
  std::uint64_t forwarded = 0;   // copies delivered
  std::uint64_t held_back = 0;   // copies the reorder probability held back
  // Copies delivered after a datagram that arrived later (from held-back copies or jitter).
  std::uint64_t reordered = 0;
  DropCounts dropped;
  DelayHistogram delay;  // delivered - arrived
  // When the configured dead spell begins (the first arrival plus outage_after_s), on the arrival
  // clock; 0: no outage configured or nothing arrived yet.
  std::int64_t outage_from_ns = 0;

  /// Copies scheduled and not yet delivered or dropped.
  std::uint64_t in_flight() const { return received + duplicated - forwarded - dropped.Total(); }
};

struct Decision {
  std::uint64_t sequence = 0;   // arrival order, from 0
  std::int64_t arrival_ns = 0;  // the arrival time used (never before the previous datagram's)
  int copies = 0;               // copies to release: 0 (dropped), 1, or 2 (duplicated)
  std::array<std::int64_t, 2> release_ns{};
};

class ImpairmentModel final {
 public:
  /// Validates `config` (std::invalid_argument naming the parameter).
  ImpairmentModel(const ImpairmentConfig& config, std::uint64_t seed);

  /// Decides the fate of one datagram of `size_bytes` arriving at `arrival_ns`. `free_buffers`
  /// is how many copies the caller can still hold; copies beyond it are dropped as queue
  /// overflow. Arrival times that run backwards are taken as the previous one.
  Decision Decide(std::int64_t arrival_ns, std::size_t size_bytes,
                  std::size_t free_buffers = std::numeric_limits<std::size_t>::max());

  /// A copy of datagram `sequence` (Decision::sequence, arrival_ns) left at `sent_ns`.
  void OnDelivered(std::uint64_t sequence, std::int64_t arrival_ns, std::int64_t sent_ns);
  /// A scheduled copy was dropped after all (send failure, no destination, stop).
  void OnUndelivered(DropCause cause);

  const ImpairmentStats& stats() const { return stats_; }
  const ImpairmentConfig& config() const { return config_; }

 private:
  // time the copy leaves the rate limiter; false: queue overflow
  bool PassRateLimit(std::int64_t arrival_ns, std::size_t size_bytes, std::int64_t* departure_ns);
  std::int64_t DrawJitter_ns();

  ImpairmentConfig config_;
  std::int64_t delay_ns_;
  std::int64_t reorder_delay_ns_;
  std::int64_t outage_from_ns_, outage_ns_;
  GilbertElliott burst_;
  RandomStream loss_draws_;
  RandomStream burst_loss_draws_;
  RandomStream burst_state_draws_;
  RandomStream duplicate_draws_;
  RandomStream jitter_draws_;
  RandomStream reorder_draws_;

  std::uint64_t next_sequence_ = 0;
  std::int64_t last_arrival_ns_ = std::numeric_limits<std::int64_t>::min();
  std::int64_t first_arrival_ns_ = std::numeric_limits<std::int64_t>::min();  // the outage's origin
  std::int64_t link_free_ns_ = std::numeric_limits<std::int64_t>::min();      // rate limiter idle from
  bool delivered_any_ = false;
  std::uint64_t highest_delivered_ = 0;
  ImpairmentStats stats_;
};

}  // namespace haptex::netsim
