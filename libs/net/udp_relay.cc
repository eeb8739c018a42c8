#include "libs/net/udp_relay.h"

#include <poll.h>
#include <sys/prctl.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "libs/base/clock.h"
#include "libs/net/udp_address.h"
#include "libs/netsim/parameter_check.h"

namespace haptex::net {
namespace {

// Above the largest UDP payload (65,507 over IPv4, 65,527 over IPv6), so that any datagram
// beyond a model's max_datagram_bytes shows its real size (MSG_TRUNC) and counts as oversize.
constexpr std::size_t kScratchBytes = 65536;
// How many datagrams one socket may deliver before due releases are sent again: a flood on one
// side must not hold back the other side's releases.
constexpr int kReceiveBatch = 64;
constexpr std::int64_t kMaxWait_ns = 100'000'000;

std::string UpstreamBindAddress(const UdpRelayConfig& config) {
  if (!config.upstream_bind_address.empty()) return config.upstream_bind_address;
  return ResolveUdpAddress(config.to_address).address().is_v6() ? "[::]:0" : "0.0.0.0:0";
}

const UdpRelayConfig& Validated(const UdpRelayConfig& config) {
  if (config.listen_address.empty()) throw std::invalid_argument("relay: no listen address");
  if (config.to_address.empty()) throw std::invalid_argument("relay: no `to` address");
  netsim::CheckRange("duration_s", config.duration_s, 0.0, 1e9);
  const std::size_t largest = std::max(config.forward.max_datagram_bytes, config.back.max_datagram_bytes);
  if (config.buffers.large_bytes < largest) {
    throw std::invalid_argument("relay: large buffers (" + std::to_string(config.buffers.large_bytes) +
                                " bytes) cannot hold max_datagram_bytes " + std::to_string(largest));
  }
  return config;
}

// The kernel rounds every poll timeout up by the thread's timer slack (50 us by default); a
// relay that should release to the microsecond asks for the smallest slack while it runs.
class MinimalTimerSlack final {
 public:
  MinimalTimerSlack() : previous_(prctl(PR_GET_TIMERSLACK, 0, 0, 0, 0)) { prctl(PR_SET_TIMERSLACK, 1UL, 0, 0, 0); }
  ~MinimalTimerSlack() {
    if (previous_ > 0) prctl(PR_SET_TIMERSLACK, static_cast<unsigned long>(previous_), 0, 0, 0);
  }
  MinimalTimerSlack(const MinimalTimerSlack&) = delete;
  MinimalTimerSlack& operator=(const MinimalTimerSlack&) = delete;

 private:
  int previous_;
};

}  // namespace

UdpRelay::Direction::Direction(const netsim::ImpairmentConfig& config, std::uint64_t seed,
                               const netsim::PacketPoolSizes& buffers, UdpEndpoint* in_socket, UdpEndpoint* out_socket,
                               std::optional<Endpoint> fixed_destination)
    : model(config, seed),
      pool(buffers),
      queue(pool.capacity()),
      in(in_socket),
      out(out_socket),
      destination(fixed_destination) {}

UdpRelay::UdpRelay(const UdpRelayConfig& config)
    : listen_(Validated(config).listen_address),
      upstream_(UpstreamBindAddress(config)),
      forward_(config.forward, config.forward_seed, config.buffers, &listen_, &upstream_,
               ResolveUdpAddress(config.to_address)),
      back_(config.back, config.back_seed, config.buffers, &upstream_, &listen_,
            config.back_to_address.empty() ? std::nullopt
                                           : std::optional<Endpoint>(ResolveUdpAddress(config.back_to_address))),
      duration_ns_(config.duration_s > 0.0 ? std::llround(config.duration_s * 1e9)
                                           : std::numeric_limits<std::int64_t>::max()),
      scratch_(kScratchBytes) {}

void UdpRelay::Run(const std::function<bool()>& stop_requested) {
  const MinimalTimerSlack slack;
  const std::int64_t start_ns = base::SteadyNowNs();
  const std::int64_t end_ns =
      duration_ns_ == std::numeric_limits<std::int64_t>::max() ? duration_ns_ : start_ns + duration_ns_;
  pollfd sockets[2] = {{listen_.native_handle(), POLLIN, 0}, {upstream_.native_handle(), POLLIN, 0}};
  // The first timestamped receive turns kernel stamps on (Linux does it through deferred work):
  // before any traffic if possible.
  ReceiveBatch(&forward_);
  ReceiveBatch(&back_);
  while (!stop_requested()) {
    std::int64_t now_ns = base::SteadyNowNs();
    if (now_ns >= end_ns) break;
    SendDue(&forward_, now_ns);
    SendDue(&back_, now_ns);

    now_ns = base::SteadyNowNs();
    std::int64_t wake_ns = std::min(end_ns, now_ns + kMaxWait_ns);
    if (!forward_.queue.empty()) wake_ns = std::min(wake_ns, forward_.queue.Top().release_ns);
    if (!back_.queue.empty()) wake_ns = std::min(wake_ns, back_.queue.Top().release_ns);
    const std::int64_t wait_ns = std::max<std::int64_t>(0, wake_ns - now_ns);
    const timespec timeout{static_cast<time_t>(wait_ns / 1'000'000'000), static_cast<long>(wait_ns % 1'000'000'000)};
    // a signal ends the wait early (EINTR); the loop then asks stop_requested()
    if (ppoll(sockets, 2, &timeout, nullptr) <= 0) continue;
    if (sockets[0].revents != 0) ReceiveBatch(&forward_);
    if (sockets[1].revents != 0) ReceiveBatch(&back_);
  }
  DropHeld(&forward_);
  DropHeld(&back_);
}

void UdpRelay::ReceiveBatch(Direction* direction) {
  for (int i = 0; i < kReceiveBatch; ++i) {
    Endpoint from;
    std::int64_t arrival_ns = 0;
    const auto size = direction->in->ReceiveOne(scratch_, &from, &arrival_ns);
    if (!size) return;
    if (direction == &forward_) last_client_ = from;

    const std::size_t size_bytes = *size;
    const netsim::Decision decision =
        direction->model.Decide(arrival_ns, size_bytes, direction->pool.FreeFor(size_bytes));
    for (int copy = 0; copy < decision.copies; ++copy) {
      // the model was told how many buffers are free, so neither can fail
      const std::uint32_t buffer = *direction->pool.Acquire(size_bytes);
      std::memcpy(direction->pool.Buffer(buffer).data(), scratch_.data(), size_bytes);
      direction->queue.Push({decision.release_ns[static_cast<std::size_t>(copy)], decision.arrival_ns,
                             decision.sequence, buffer, static_cast<std::uint32_t>(size_bytes)});
    }
  }
}

void UdpRelay::SendDue(Direction* direction, std::int64_t now_ns) {
  while (!direction->queue.empty() && direction->queue.Top().release_ns <= now_ns) {
    const netsim::ScheduledCopy copy = direction->queue.Pop();
    const Endpoint* to = direction->destination ? &*direction->destination : last_client_ ? &*last_client_ : nullptr;
    if (to == nullptr) {
      direction->model.OnUndelivered(netsim::DropCause::kNoDestination);
    } else {
      const std::int64_t sent_ns = base::SteadyNowNs();
      const auto bytes = direction->pool.Buffer(copy.buffer).first(copy.size_bytes);
      if (direction->out->SendTo(bytes, *to)) {
        direction->model.OnDelivered(copy.sequence, copy.arrival_ns, sent_ns);
      } else {
        direction->model.OnUndelivered(netsim::DropCause::kSendFailed);
      }
    }
    direction->pool.Release(copy.buffer);
  }
}

void UdpRelay::DropHeld(Direction* direction) {
  while (!direction->queue.empty()) {
    direction->pool.Release(direction->queue.Pop().buffer);
    direction->model.OnUndelivered(netsim::DropCause::kUnsentAtStop);
  }
}

}  // namespace haptex::net
