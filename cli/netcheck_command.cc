#include "cli/netcheck_command.h"

#include <atomic>
#include <chrono>
#include <iostream>
#include <memory>
#include <thread>

#include <unistd.h>

#include "cli/netcheck_report.h"
#include "libs/base/clock.h"
#include "libs/net/messenger.h"
#include "libs/net/udp_address.h"
#include "libs/runtime/periodic_loop.h"
#include "libs/runtime/shutdown_signal.h"
#include "libs/scene/session_key_source.h"

namespace haptex::cli {
namespace {

// the server's name, which probes address their datagrams to
constexpr std::string_view kServeName = "netcheck_serve";

struct ServeOptions {
  std::string bind;
  double seconds = 0;
  std::string key_file;
};

constexpr std::uint64_t kMaxProbes = 10'000'000;  // 80 MB of samples

struct ProbeOptions {
  std::string to;
  std::string bind;  // empty: any local address of the target's family
  double rate_hz = 1000;
  double seconds = 5;
  std::size_t padding_bytes = 200;
  int grace_ms = 500;
  bool json = false;
  std::string key_file;
};

void PrintDrops(const net::DropCounters& counters, std::ostream& out) {
  for (std::size_t i = 1; i < net::kDropReasonCount; ++i) {
    const auto reason = static_cast<net::DropReason>(i);
    if (counters.Get(reason) != 0) out << " " << net::DropReasonName(reason) << "=" << counters.Get(reason);
  }
}

int Serve(const ServeOptions& options) {
  const net::SessionKey key = scene::LoadSessionKey(options.key_file);
  net::MessengerConfig config;
  config.bind_address = options.bind;
  config.identity = {std::string(kServeName), 0, key.DerivedSessionId()};
  net::Messenger messenger(key, config);
  runtime::InstallShutdownHandlers();
  std::cout << "netcheck serve: listening on " << net::FormatUdpAddress(messenger.local_endpoint()) << std::endl;

  v1::NetProbe reply;
  std::uint64_t replies = 0;
  const auto start = std::chrono::steady_clock::now();
  auto expired = [&] {
    return options.seconds > 0 &&
           std::chrono::steady_clock::now() - start > std::chrono::duration<double>(options.seconds);
  };
  while (!runtime::ShutdownRequested() && !expired()) {
    if (!messenger.WaitReadable(std::chrono::milliseconds(100))) continue;
    messenger.Drain([&](const v1::Envelope& envelope, const net::Messenger::Endpoint& from) {
      if (envelope.body_case() != v1::Envelope::kNetProbe || envelope.net_probe().is_reply()) return;
      reply = envelope.net_probe();
      reply.set_is_reply(true);
      if (messenger.SendTo(from, envelope.sender(), reply)) ++replies;
    });
  }
  std::cout << "netcheck serve: " << replies << " replies; accepted " << messenger.received().accepted() << "; dropped";
  PrintDrops(messenger.received(), std::cout);
  std::cout << (messenger.received().TotalDropped() == 0 ? " none" : "") << std::endl;
  return 0;
}

int Probe(const ProbeOptions& options) {
  const auto probes = static_cast<std::uint64_t>(std::ceil(options.rate_hz * options.seconds));
  if (probes > kMaxProbes) {
    throw std::invalid_argument("rate x seconds = " + std::to_string(probes) + " probes; at most " +
                                std::to_string(kMaxProbes) + " per run");
  }
  const net::SessionKey key = scene::LoadSessionKey(options.key_file);
  net::MessengerConfig config;
  config.bind_address = options.bind;
  if (config.bind_address.empty()) {
    config.bind_address = net::ResolveUdpAddress(options.to).address().is_v6() ? "[::]:0" : "0.0.0.0:0";
  }
  // one name per run: two probes at once must not look like restarts of each other
  config.identity = {"netcheck_probe_" + std::to_string(getpid()), 0, key.DerivedSessionId()};
  net::Messenger messenger(key, config);
  const auto server = messenger.AddPeer(kServeName, options.to);
  runtime::InstallShutdownHandlers();

  ProbeRecorder recorder(probes);
  std::atomic<bool> receiving{true};

  // Replies are timestamped on their own thread, so the round trip is not rounded up to the
  // send period.
  std::thread receiver([&] {
    while (receiving.load(std::memory_order_acquire)) {
      if (!messenger.WaitReadable(std::chrono::milliseconds(20))) continue;
      messenger.Drain([&](const v1::Envelope& envelope, const net::Messenger::Endpoint&) {
        if (envelope.body_case() != v1::Envelope::kNetProbe || !envelope.net_probe().is_reply()) return;
        const auto& probe = envelope.net_probe();
        recorder.OnReply(probe.probe_sequence(), base::SteadyNowNs() - probe.probe_send_time_ns());
      });
    }
  });

  v1::NetProbe probe;
  probe.set_padding(std::string(options.padding_bytes, '\0'));
  std::uint64_t sent = 0;
  runtime::PeriodicLoop loop("netcheck_probe", options.rate_hz);
  loop.Run(
      [&](const runtime::TickInfo&) {
        probe.set_probe_sequence(sent + 1);
        probe.set_probe_send_time_ns(base::SteadyNowNs());
        messenger.Send(server, probe);
        ++sent;
      },
      [&] { return sent >= probes || runtime::ShutdownRequested(); });

  // Late replies still count until the grace period ends.
  std::this_thread::sleep_for(std::chrono::milliseconds(options.grace_ms));
  receiving.store(false, std::memory_order_release);
  receiver.join();

  NetcheckReport report;
  report.target = options.to;
  report.rate_hz = options.rate_hz;
  report.seconds = static_cast<double>(sent) / options.rate_hz;
  report.datagram_bytes = messenger.last_sent_bytes();
  report.send_failures = messenger.send_failures();
  report.send_overruns = loop.stats().overruns;
  recorder.OnRejected(messenger.received().TotalDropped());
  recorder.Summarise(sent, LinkVerdictLimits{}, &report);
  std::cout << (options.json ? ReportToJson(report) + "\n" : ReportToText(report));
  return report.verdict == "good" || report.verdict == "usable" || report.verdict == "global_only" ? 0 : 3;
}

}  // namespace

void AddNetcheckCommand(CLI::App& app, int* exit_code) {
  CLI::App* netcheck =
      app.add_subcommand("netcheck", "Measure a link for haptic use: run `serve` on one machine, `probe` on the other");
  netcheck->require_subcommand(1);

  auto serve_options = std::make_shared<ServeOptions>();
  CLI::App* serve = netcheck->add_subcommand("serve", "Answer probes (until Ctrl-C or --seconds)");
  serve->add_option("--bind", serve_options->bind, "host:port to listen on, e.g. 0.0.0.0:7600")->required();
  serve->add_option("--seconds", serve_options->seconds, "stop after this long (0: until Ctrl-C)")
      ->check(CLI::Range(0.0, 1e7));
  serve->add_option("--key-file", serve_options->key_file,
                    "file with the 64-hex-digit session key (default: $HAPTEX_SESSION_KEY)");
  serve->callback([serve_options, exit_code] { *exit_code = Serve(*serve_options); });

  auto probe_options = std::make_shared<ProbeOptions>();
  CLI::App* probe = netcheck->add_subcommand("probe", "Send probes to a server and report the link");
  probe->add_option("--to", probe_options->to, "host:port of `haptex netcheck serve`")->required();
  probe->add_option("--bind", probe_options->bind, "local host:port (default: any, port chosen)");
  probe->add_option("--rate", probe_options->rate_hz, "probes per second")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 20000.0));
  probe->add_option("--seconds", probe_options->seconds, "how long to probe")
      ->capture_default_str()
      ->check(CLI::Range(0.01, 3600.0));
  probe->add_option("--padding", probe_options->padding_bytes, "payload bytes per probe")
      ->capture_default_str()
      ->check(CLI::Range(0, 59000));
  probe->add_option("--grace-ms", probe_options->grace_ms, "wait for late replies")
      ->capture_default_str()
      ->check(CLI::Range(0, 60000));
  probe->add_flag("--json", probe_options->json, "print one JSON object");
  probe->add_option("--key-file", probe_options->key_file,
                    "file with the 64-hex-digit session key (default: $HAPTEX_SESSION_KEY)");
  probe->callback([probe_options, exit_code] { *exit_code = Probe(*probe_options); });
}

}  // namespace haptex::cli
