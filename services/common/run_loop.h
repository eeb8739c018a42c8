#pragma once
// The one tick of every haptex service: read (drain the messenger: Control to the context and the
// loop, every other message to the loop), update, write (the loop sends through the context),
// then Health when due. A loop object provides
//   void Read(const v1::Envelope&, double t_s);
//   void Update(double t_s, double dt_s);
//   void Write(Outbox&);
// and, when it acts on Control commands, void OnControl(v1::Control::Command).

#include <cstddef>
#include <limits>

#include "libs/base/clock.h"
#include "libs/runtime/latency_histogram.h"
#include "libs/runtime/periodic_loop.h"
#include "services/common/service_context.h"

namespace haptex::services {

/// Drains the messenger once (at most `max_datagrams`): Control to the context (and the loop when
/// addressed to this service), everything else to loop.Read.
template <class Loop>
void ReadMessages(ServiceContext& context, Loop& loop, double t_s,
                  std::size_t max_datagrams = net::Messenger::kDefaultDrainBound,
                  std::int64_t until_ns = std::numeric_limits<std::int64_t>::max()) {
  context.messenger().Drain(
      [&](const v1::Envelope& envelope, const net::Messenger::Endpoint&) {
        switch (context.HandleControl(envelope)) {
          case ServiceContext::ControlResult::kForUs:
            if constexpr (requires { loop.OnControl(v1::Control::COMMAND_UNSPECIFIED); }) {
              loop.OnControl(context.last_command());
            }
            return;
          case ServiceContext::ControlResult::kForOthers:
            return;
          case ServiceContext::ControlResult::kNotControl:
            loop.Read(envelope, t_s);
            return;
        }
      },
      max_datagrams, until_ns);
}

/// Runs `loop` on `periodic` until the service is asked to stop (signal, Control SHUTDOWN,
/// --duration). After skipped cycles the loop is told the time that really passed. With
/// `update_time`, the time Update and Write take (the tick without its socket reads) goes there.
template <class Loop>
void RunLoop(ServiceContext& context, runtime::PeriodicLoop& periodic, Loop& loop,
             runtime::LatencyHistogram* update_time = nullptr) {
  std::int64_t now_ns = context.start_ns();
  periodic.Run(
      [&](const runtime::TickInfo& tick) {
        now_ns = tick.now_ns;
        const double t_s = context.SecondsSinceStart(tick.now_ns);
        ReadMessages(context, loop, t_s);
        const std::int64_t update_start_ns = update_time != nullptr ? base::SteadyNowNs() : 0;
        loop.Update(t_s, tick.dt_s * static_cast<double>(1 + tick.skipped));
        loop.Write(context);
        if (update_time != nullptr) update_time->Record(base::SteadyNowNs() - update_start_ns);
        context.Tick(tick.now_ns);
      },
      [&] { return context.StopRequested(now_ns); });
}

}  // namespace haptex::services
