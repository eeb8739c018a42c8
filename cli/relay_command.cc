#include "cli/relay_command.h"

#include <chrono>
#include <fstream>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>

#include "cli/per_direction.h"
#include "cli/relay_report.h"
#include "libs/net/udp_address.h"
#include "libs/net/udp_relay.h"
#include "libs/netsim/parameter_check.h"
#include "libs/runtime/shutdown_signal.h"

namespace haptex::cli {
namespace {

using netsim::ImpairmentConfig;

// Flags as typed: each number flag is parsed by per_direction.h, so NaN, infinity and garbage are
// refused the same way everywhere (CLI11's range checks let NaN through).
struct RelayOptions {
  std::string listen;
  std::string to;
  std::string upstream_bind;
  std::string back_to;
  std::string delay_ms = "0";
  std::string jitter_ms = "0";
  std::string jitter_dist = "uniform";
  std::string loss = "0";
  std::string burst_loss;
  std::string burst_loss_forward;
  std::string burst_loss_back;
  std::string reorder = "0";
  std::string reorder_delay_ms = "10";
  std::string duplicate = "0";
  std::string rate_kbps = "0";
  std::string outage_after_s = "0";
  std::string outage_s = "0";
  std::string queue_bytes = std::to_string(ImpairmentConfig{}.queue_bytes);
  std::string max_datagram_bytes = std::to_string(ImpairmentConfig{}.max_datagram_bytes);
  std::string seed = "1";
  std::string duration_s = "0";
  std::string json_path;
};

// Parses a per-direction number flag, checks each value with `check(name, value)` under the name
// the user typed, and stores it into each direction's config with `store`.
template <typename Check, typename Store>
void ApplyNumber(std::string_view flag, const std::string& text, Check check, Store store,
                 net::UdpRelayConfig* config) {
  const PerDirection<double> values = ParsePerDirectionNumber(flag, text);
  check(DirectionFlagName(flag, values.differ, false), values.forward);
  check(DirectionFlagName(flag, values.differ, true), values.back);
  store(&config->forward, values.forward);
  store(&config->back, values.back);
}

netsim::GilbertElliottConfig ParseBurst(std::string_view flag, const std::string& text) {
  const std::vector<double> values = ParseNumberList(flag, text, 2, 4);
  netsim::GilbertElliottConfig burst;
  burst.p_good_to_bad = values[0];
  burst.p_bad_to_good = values[1];
  if (values.size() > 2) burst.loss_bad = values[2];
  if (values.size() > 3) burst.loss_good = values[3];
  try {
    netsim::ValidateGilbertElliott(burst, "");
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string(flag) + " P,R[,LOSS_BAD[,LOSS_GOOD]]: " + e.what());
  }
  return burst;
}

net::UdpRelayConfig BuildConfig(const RelayOptions& options) {
  net::UdpRelayConfig config;
  config.listen_address = options.listen;
  config.to_address = options.to;
  config.upstream_bind_address = options.upstream_bind;
  config.back_to_address = options.back_to;

  const auto range = [](double min, double max) {
    return [min, max](const std::string& name, double value) { netsim::CheckRange(name, value, min, max); };
  };
  const auto whole = [](double min, double max) {
    return [min, max](const std::string& name, double value) { netsim::CheckWholeNumber(name, value, min, max); };
  };
  const auto probability = [](const std::string& name, double value) { netsim::CheckProbability(name, value); };
  using C = ImpairmentConfig;
  ApplyNumber(
      "--delay-ms", options.delay_ms, range(0, C::kMaxDelay_ms), [](C* c, double v) { c->delay_ms = v; }, &config);
  ApplyNumber(
      "--jitter-ms", options.jitter_ms, range(0, C::kMaxDelay_ms), [](C* c, double v) { c->jitter_ms = v; }, &config);
  ApplyNumber(
      "--loss", options.loss, probability, [](C* c, double v) { c->loss = v; }, &config);
  ApplyNumber(
      "--reorder", options.reorder, probability, [](C* c, double v) { c->reorder = v; }, &config);
  ApplyNumber(
      "--reorder-delay-ms", options.reorder_delay_ms, range(0, C::kMaxDelay_ms),
      [](C* c, double v) { c->reorder_delay_ms = v; }, &config);
  ApplyNumber(
      "--duplicate", options.duplicate, probability, [](C* c, double v) { c->duplicate = v; }, &config);
  ApplyNumber(
      "--rate-kbps", options.rate_kbps, range(0, C::kMaxRate_kbps), [](C* c, double v) { c->rate_kbps = v; }, &config);
  ApplyNumber(
      "--outage-after-s", options.outage_after_s, range(0, C::kMaxOutage_s),
      [](C* c, double v) { c->outage_after_s = v; }, &config);
  ApplyNumber(
      "--outage-s", options.outage_s, range(0, C::kMaxOutage_s), [](C* c, double v) { c->outage_s = v; }, &config);
  ApplyNumber(
      "--queue-bytes", options.queue_bytes, whole(1, static_cast<double>(C::kMaxQueue_bytes)),
      [](C* c, double v) { c->queue_bytes = static_cast<std::size_t>(v); }, &config);
  ApplyNumber(
      "--max-datagram-bytes", options.max_datagram_bytes, whole(1, static_cast<double>(C::kMaxDatagram_bytes)),
      [](C* c, double v) { c->max_datagram_bytes = static_cast<std::size_t>(v); }, &config);

  const PerDirection<std::string> dist = ParsePerDirectionWord("--jitter-dist", options.jitter_dist);
  try {
    config.forward.jitter_distribution = netsim::ParseJitterDistribution(dist.forward);
    config.back.jitter_distribution = netsim::ParseJitterDistribution(dist.back);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("--jitter-dist: ") + e.what());
  }

  if (!options.burst_loss.empty()) {
    config.forward.burst = config.back.burst = ParseBurst("--burst-loss", options.burst_loss);
  }
  if (!options.burst_loss_forward.empty()) {
    config.forward.burst = ParseBurst("--burst-loss-forward", options.burst_loss_forward);
  }
  if (!options.burst_loss_back.empty()) {
    config.back.burst = ParseBurst("--burst-loss-back", options.burst_loss_back);
  }

  const PerDirection<std::uint64_t> seeds = ParsePerDirectionSeed("--seed", options.seed);
  config.forward_seed = seeds.forward;
  config.back_seed = seeds.back;
  config.duration_s = ParseFiniteNumber("--duration", options.duration_s);
  netsim::CheckRange("--duration", config.duration_s, 0.0, 1e7);

  // the checks above name the flags; these only back them up
  netsim::Validate(config.forward);
  netsim::Validate(config.back);
  return config;
}

int RunRelay(const RelayOptions& options) {
  const net::UdpRelayConfig config = BuildConfig(options);
  // refuse an unwritable report file before relaying anything, not after
  std::ofstream json_file;
  if (!options.json_path.empty()) {
    json_file.open(options.json_path);
    if (!json_file) throw std::invalid_argument("--json: cannot write " + options.json_path);
  }
  runtime::InstallShutdownHandlers();
  net::UdpRelay relay(config);

  RelayReport report;
  report.listen = net::FormatUdpAddress(relay.listen_endpoint());
  report.upstream = net::FormatUdpAddress(relay.upstream_endpoint());
  report.to = config.to_address;
  report.back_to = config.back_to_address;
  std::cout << "relay: listening on " << report.listen << ", upstream " << report.upstream << ", to " << report.to
            << ", back to " << (report.back_to.empty() ? "the last client" : report.back_to) << std::endl;

  const auto start = std::chrono::steady_clock::now();
  relay.Run([] { return runtime::ShutdownRequested(); });
  report.duration_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  report.forward = {config.forward, config.forward_seed, relay.forward_stats()};
  report.back = {config.back, config.back_seed, relay.back_stats()};

  std::cout << RelayReportToText(report) << std::flush;
  if (json_file.is_open()) {
    json_file << RelayReportToJson(report) << "\n";
    json_file.close();
    if (!json_file) throw std::runtime_error("--json: writing " + options.json_path + " failed");
  }
  return 0;
}

}  // namespace

void AddRelayCommand(CLI::App& app, int* exit_code) {
  auto options = std::make_shared<RelayOptions>();
  CLI::App* relay =
      app.add_subcommand("relay",
                         "Relay UDP between clients and a server with delay, jitter, loss, bursts, reordering, "
                         "duplication and a rate limit (docs/relay.md). Impairment flags take one value for both "
                         "directions or FORWARD,BACK (forward: --listen -> --to)");
  relay->add_option("--listen", options->listen, "host:port clients send to")->required();
  relay->add_option("--to", options->to, "host:port of the server side")->required();
  relay->add_option("--upstream-bind", options->upstream_bind,
                    "host:port of the relay's socket towards the server (default: any, port chosen)");
  relay->add_option("--back-to", options->back_to, "host:port replies go to (default: the last client seen)");
  relay->add_option("--delay-ms", options->delay_ms, "added delay [ms]")->capture_default_str();
  relay
      ->add_option("--jitter-ms", options->jitter_ms,
                   "jitter [ms]: half-width (uniform) or standard deviation (normal)")
      ->capture_default_str();
  relay->add_option("--jitter-dist", options->jitter_dist, "uniform or normal")->capture_default_str();
  relay->add_option("--loss", options->loss, "independent loss probability")->capture_default_str();
  relay->add_option("--burst-loss", options->burst_loss,
                    "Gilbert-Elliott burst loss for both directions: P,R[,LOSS_BAD[,LOSS_GOOD]] with "
                    "P = P(good->bad), R = P(bad->good) per datagram, loss in the bad state "
                    "(default 1) and in the good state (default 0)");
  relay->add_option("--burst-loss-forward", options->burst_loss_forward,
                    "the same, forward direction only (overrides --burst-loss)");
  relay->add_option("--burst-loss-back", options->burst_loss_back,
                    "the same, back direction only (overrides --burst-loss)");
  relay->add_option("--reorder", options->reorder, "probability that a datagram is held back by --reorder-delay-ms")
      ->capture_default_str();
  relay->add_option("--reorder-delay-ms", options->reorder_delay_ms, "extra delay of held-back datagrams [ms]")
      ->capture_default_str();
  relay->add_option("--duplicate", options->duplicate, "duplication probability")->capture_default_str();
  relay->add_option("--rate-kbps", options->rate_kbps, "rate limit [kbit/s] (0: none)")->capture_default_str();
  relay
      ->add_option("--outage-after-s", options->outage_after_s,
                   "a dead link from this long after the first datagram [s]")
      ->capture_default_str();
  relay->add_option("--outage-s", options->outage_s, "for this long: every datagram dropped [s] (0: none)")
      ->capture_default_str();
  relay
      ->add_option("--queue-bytes", options->queue_bytes,
                   "bytes that may wait for the rate limit; beyond: queue overflow")
      ->capture_default_str();
  relay->add_option("--max-datagram-bytes", options->max_datagram_bytes, "larger datagrams are dropped as oversize")
      ->capture_default_str();
  relay->add_option("--seed", options->seed, "seed: S (back uses S+1) or FORWARD,BACK")->capture_default_str();
  relay->add_option("--duration", options->duration_s, "stop after this many seconds (0: at SIGINT/SIGTERM)")
      ->capture_default_str();
  relay->add_option("--json", options->json_path, "also write the report as JSON to this file");
  relay->callback([options, exit_code] { *exit_code = RunRelay(*options); });
}

}  // namespace haptex::cli
