// `haptex relay` as a real process between two real UDP sockets on loopback. Assertions are on
// counts and lower bounds of delay, never on how fast this (shared) machine is.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstring>
#include <memory>
#include <random>
#include <regex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "libs/net/udp_endpoint.h"
#include "tests/support/subprocess.h"
#include "tests/support/test_paths.h"

namespace haptex {
namespace {

using namespace std::chrono_literals;
using ::testing::HasSubstr;
using testing::Subprocess;
using Endpoint = net::UdpEndpoint::Endpoint;

std::string Haptex() { return testing::BuildDir() + "/cli/haptex"; }

std::int64_t NowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

Endpoint Loopback(int port) { return Endpoint(asio::ip::make_address("127.0.0.1"), static_cast<unsigned short>(port)); }

std::string Address(const net::UdpEndpoint& socket) { return "127.0.0.1:" + std::to_string(socket.local_port()); }

// Test datagrams: a marker (garbage never starts with it), an index, the send time.
constexpr std::uint64_t kMarker = 0x52454c4159544553ull;  // "RELAYTES"
constexpr std::size_t kStampedBytes = 24;

std::vector<std::uint8_t> Stamped(std::uint64_t index, std::int64_t sent_ns) {
  std::vector<std::uint8_t> bytes(kStampedBytes);
  std::memcpy(bytes.data(), &kMarker, 8);
  std::memcpy(bytes.data() + 8, &index, 8);
  std::memcpy(bytes.data() + 16, &sent_ns, 8);
  return bytes;
}

struct Arrival {
  std::uint64_t index = 0;
  std::int64_t sent_ns = 0;
  std::int64_t received_ns = 0;
  Endpoint from;
};

// Everything waiting on `socket` that carries the marker; the rest is counted in *others.
std::vector<Arrival> Drain(net::UdpEndpoint* socket, std::size_t* others = nullptr) {
  std::vector<Arrival> out;
  std::vector<std::uint8_t> buffer(70000);
  Arrival a;
  while (const auto size = socket->ReceiveOne(buffer, &a.from)) {
    std::uint64_t marker = 0;
    if (*size == kStampedBytes) std::memcpy(&marker, buffer.data(), 8);
    if (marker != kMarker) {
      if (others) ++*others;
      continue;
    }
    a.received_ns = NowNs();
    std::memcpy(&a.index, buffer.data() + 8, 8);
    std::memcpy(&a.sent_ns, buffer.data() + 16, 8);
    out.push_back(a);
  }
  return out;
}

// The "forward" or "back" object of the JSON report.
std::string Direction(const std::string& json, const std::string& name) {
  const std::size_t forward = json.find("\"forward\":{");
  const std::size_t back = json.find("\"back\":{");
  if (forward == std::string::npos || back == std::string::npos) {
    ADD_FAILURE() << "no directions in " << json;
    return "";
  }
  return name == "forward" ? json.substr(forward, back - forward) : json.substr(back);
}

std::uint64_t Count(const std::string& section, const std::string& key) {
  std::smatch match;
  if (!std::regex_search(section, match, std::regex("\"" + key + "\":([0-9]+)[,}]"))) {
    ADD_FAILURE() << "no " << key << " in " << section;
    return 0;
  }
  return std::stoull(match[1]);
}

std::uint64_t Dropped(const std::string& section, const std::string& cause) {
  const std::size_t dropped = section.find("\"dropped\":{");
  return dropped == std::string::npos ? 0 : Count(section.substr(dropped), cause);
}

// Every datagram received is forwarded or dropped exactly once, with its duplicates.
void ExpectBalanced(const std::string& section) {
  EXPECT_EQ(Count(section, "forwarded") + Count(section, "dropped_total"),
            Count(section, "received") + Count(section, "duplicated"))
      << section;
  EXPECT_EQ(Count(section, "in_flight"), 0u) << section;
}

class RelayProcess {
 public:
  explicit RelayProcess(std::vector<std::string> flags) {
    std::vector<std::string> argv = {Haptex(), "relay"};
    argv.insert(argv.end(), flags.begin(), flags.end());
    process_ = std::make_unique<Subprocess>(argv);
    const std::regex started("listening on 127\\.0\\.0\\.1:([0-9]+), upstream ([0-9.]+):([0-9]+)");
    std::smatch match;
    for (int i = 0; i < 1000; ++i) {
      const std::string out = process_->Stdout();
      if (std::regex_search(out, match, started)) {
        listen_port_ = std::stoi(match[1]);
        upstream_host_ = match[2];
        upstream_port_ = std::stoi(match[3]);
        return;
      }
      if (process_->WaitFor(10ms)) break;
    }
    ADD_FAILURE() << "relay did not start: " << process_->Stdout() << process_->Stderr();
  }

  Endpoint listen() const { return Loopback(listen_port_); }
  Endpoint upstream() const { return Loopback(upstream_port_); }
  const std::string& upstream_host() const { return upstream_host_; }

  // Stops it with `signal_number`; its exit code.
  int Stop(int signal_number = SIGTERM) {
    process_->Signal(signal_number);
    const auto code = process_->WaitFor(10s);
    EXPECT_TRUE(code.has_value()) << "relay ignored signal " << signal_number;
    return code.value_or(-1);
  }
  Subprocess& process() { return *process_; }

 private:
  std::unique_ptr<Subprocess> process_;
  int listen_port_ = 0;
  int upstream_port_ = 0;
  std::string upstream_host_;
};

std::string JsonPath(const std::string& name) {
  return ::testing::TempDir() + "/relay_" + name + "_" + std::to_string(getpid()) + ".json";
}

// Keeps draining until nothing has come for `quiet`.
template <typename OnIdle>
void DrainUntilQuiet(std::chrono::milliseconds quiet, OnIdle drain_once) {
  auto last = std::chrono::steady_clock::now();
  while (std::chrono::steady_clock::now() - last < quiet) {
    if (drain_once()) last = std::chrono::steady_clock::now();
    std::this_thread::sleep_for(1ms);
  }
}

TEST(RelayCommandTest, DelaysDropsAndReportsExactCountsBothWays) {
  net::UdpEndpoint client("127.0.0.1:0");
  net::UdpEndpoint server("127.0.0.1:0");
  const std::string json_path = JsonPath("counts");
  RelayProcess relay({"--listen", "127.0.0.1:0", "--to", Address(server), "--delay-ms", "20,10", "--loss", "0.2,0",
                      "--seed", "7", "--json", json_path});
  constexpr int kSent = 2000;
  std::vector<Arrival> at_server, at_client;
  const auto pump = [&] {
    const auto server_new = Drain(&server);
    for (const Arrival& a : server_new) {
      // echo, as a service answers its peer: here the source, the relay's upstream socket
      EXPECT_TRUE(server.SendTo(Stamped(a.index, a.sent_ns), a.from));
    }
    const auto client_new = Drain(&client);
    at_server.insert(at_server.end(), server_new.begin(), server_new.end());
    at_client.insert(at_client.end(), client_new.begin(), client_new.end());
    return !server_new.empty() || !client_new.empty();
  };
  for (int i = 0; i < kSent; ++i) {
    ASSERT_TRUE(client.SendTo(Stamped(static_cast<std::uint64_t>(i), NowNs()), relay.listen()));
    pump();
    std::this_thread::sleep_for(200us);
  }
  DrainUntilQuiet(500ms, pump);
  ASSERT_EQ(relay.Stop(SIGTERM), 0) << relay.process().Stderr();

  // each arrival at least the configured delay after its send (less a microsecond for moving the
  // kernel's receive stamp onto the steady clock)
  for (const Arrival& a : at_server) ASSERT_GE(a.received_ns - a.sent_ns, 20'000'000 - 1'000);
  for (const Arrival& a : at_client) ASSERT_GE(a.received_ns - a.sent_ns, 30'000'000 - 2'000);
  // forward loss 0.2 of 2000: within 5 binomial standard deviations
  const double lost = kSent - static_cast<double>(at_server.size());
  EXPECT_NEAR(lost, 0.2 * kSent, 5 * std::sqrt(kSent * 0.2 * 0.8));
  EXPECT_EQ(at_client.size(), at_server.size());  // no loss back

  const std::string json = testing::ReadFileOrEmpty(json_path);
  const std::string forward = Direction(json, "forward");
  const std::string back = Direction(json, "back");
  EXPECT_EQ(Count(forward, "received"), static_cast<std::uint64_t>(kSent));
  EXPECT_EQ(Count(forward, "forwarded"), at_server.size());
  EXPECT_EQ(Dropped(forward, "loss"), kSent - at_server.size());
  EXPECT_EQ(Count(forward, "dropped_total"), kSent - at_server.size());
  EXPECT_EQ(Count(forward, "duplicated"), 0u);
  EXPECT_EQ(Count(forward, "reordered"), 0u);
  EXPECT_EQ(Count(forward, "seed"), 7u);
  EXPECT_EQ(Count(back, "seed"), 8u);
  EXPECT_EQ(Count(back, "received"), at_server.size());
  EXPECT_EQ(Count(back, "forwarded"), at_client.size());
  EXPECT_EQ(Count(back, "dropped_total"), 0u);
  ExpectBalanced(forward);
  ExpectBalanced(back);
  const std::string out = relay.process().Stdout();
  EXPECT_THAT(out, HasSubstr("forward: received 2000, forwarded " + std::to_string(at_server.size())));
  EXPECT_THAT(out, HasSubstr("delay ms p50 "));
}

TEST(RelayCommandTest, AServerSendingToTheFixedUpstreamPortReachesBackTo) {
  net::UdpEndpoint client("127.0.0.1:0");
  net::UdpEndpoint server("127.0.0.1:0");
  const std::string json_path = JsonPath("back_to");
  RelayProcess relay({"--listen", "127.0.0.1:0", "--to", Address(server), "--upstream-bind", "127.0.0.1:0", "--back-to",
                      Address(client), "--delay-ms", "0,15", "--json", json_path});
  EXPECT_EQ(relay.upstream_host(), "127.0.0.1");  // bound where asked
  // the server has heard nothing: it sends to the relay as the peer on its command line
  constexpr int kSent = 100;
  for (int i = 0; i < kSent; ++i) {
    ASSERT_TRUE(server.SendTo(Stamped(static_cast<std::uint64_t>(i), NowNs()), relay.upstream()));
  }
  std::vector<Arrival> at_client;
  DrainUntilQuiet(500ms, [&] {
    const auto fresh = Drain(&client);
    at_client.insert(at_client.end(), fresh.begin(), fresh.end());
    return !fresh.empty();
  });
  ASSERT_EQ(at_client.size(), static_cast<std::size_t>(kSent));
  for (std::size_t i = 0; i < at_client.size(); ++i) {
    EXPECT_EQ(at_client[i].index, i);  // in order
    EXPECT_GE(at_client[i].received_ns - at_client[i].sent_ns, 15'000'000 - 1'000);
    EXPECT_EQ(at_client[i].from, relay.listen());
  }
  ASSERT_EQ(relay.Stop(SIGINT), 0);
  const std::string json = testing::ReadFileOrEmpty(json_path);
  EXPECT_THAT(json, HasSubstr("\"back_to\":\"" + Address(client) + "\""));
  EXPECT_EQ(Count(Direction(json, "back"), "forwarded"), static_cast<std::uint64_t>(kSent));
  EXPECT_EQ(Count(Direction(json, "forward"), "received"), 0u);
}

TEST(RelayCommandTest, BadFlagsExitWith2AndNameTheFlag) {
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"--loss", "nan"}, "--loss: 'nan' is not a finite number"},
      {{"--delay-ms", "inf"}, "--delay-ms: 'inf' is not a finite number"},
      {{"--delay-ms", "-5"}, "--delay-ms must be within [0, 60000], got -5"},
      {{"--jitter-ms", "1e9"}, "--jitter-ms must be within"},
      {{"--loss", "0.1,1.5"}, "--loss (back) must be a probability within [0, 1], got 1.5"},
      {{"--duplicate", "-0.1"}, "--duplicate must be a probability"},
      {{"--reorder", "2"}, "--reorder must be a probability"},
      {{"--delay-ms", "1,2,3"}, "--delay-ms: one value for both directions or two as FORWARD,BACK"},
      {{"--jitter-dist", "cauchy"}, "--jitter-dist: jitter distribution must be 'uniform' or 'normal'"},
      {{"--rate-kbps", "-1"}, "--rate-kbps must be within"},
      {{"--rate-kbps", "NaN,5"}, "--rate-kbps: 'NaN' is not a finite number"},
      {{"--queue-bytes", "1.5"}, "--queue-bytes must be a whole number"},
      {{"--max-datagram-bytes", "70000"}, "--max-datagram-bytes must be within [1, 65535]"},
      {{"--burst-loss", "0.1"}, "--burst-loss: expected 2 to 4 comma-separated numbers"},
      {{"--burst-loss", "0.1,0"}, "--burst-loss P,R[,LOSS_BAD[,LOSS_GOOD]]: r must be > 0 when p > 0"},
      {{"--burst-loss-back", "0.1,1.2"}, "--burst-loss-back P,R[,LOSS_BAD[,LOSS_GOOD]]: r must be a probability"},
      {{"--seed", "-3"}, "--seed: '-3' is not a whole number"},
      {{"--duration", "nan"}, "--duration: 'nan' is not a finite number"},
      {{"--duration", "-1"}, "--duration must be within"},
      {{"--json", "/nonexistent-dir/x.json"}, "--json: cannot write /nonexistent-dir/x.json"},
  };
  for (const auto& [flags, message] : cases) {
    std::vector<std::string> argv = {Haptex(), "relay", "--listen", "127.0.0.1:0", "--to", "127.0.0.1:9"};
    argv.insert(argv.end(), flags.begin(), flags.end());
    Subprocess relay(argv);
    EXPECT_EQ(relay.WaitFor(10s), 2) << flags[0] << " " << flags[1];
    EXPECT_THAT(relay.Stderr(), HasSubstr(message)) << flags[0] << " " << flags[1];
  }
  Subprocess no_port({Haptex(), "relay", "--listen", "127.0.0.1", "--to", "127.0.0.1:9"});
  EXPECT_EQ(no_port.WaitFor(10s), 2);
  EXPECT_THAT(no_port.Stderr(), HasSubstr("no port"));
  Subprocess no_to({Haptex(), "relay", "--listen", "127.0.0.1:0"});
  EXPECT_EQ(no_to.WaitFor(10s), 2);
  EXPECT_THAT(no_to.Stderr(), HasSubstr("--to"));
}

TEST(RelayCommandTest, StopsAfterTheDurationAndReports) {
  Subprocess relay({Haptex(), "relay", "--listen", "127.0.0.1:0", "--to", "127.0.0.1:9", "--duration", "0.3"});
  ASSERT_EQ(relay.WaitFor(30s), 0) << relay.Stderr();
  EXPECT_THAT(relay.Stdout(), HasSubstr("forward: received 0, forwarded 0"));
  EXPECT_THAT(relay.Stdout(), HasSubstr("back: received 0"));
}

TEST(RelayCommandTest, SurvivesAFloodOfOversizeAndGarbageDatagrams) {
  net::UdpEndpoint client("127.0.0.1:0");
  net::UdpEndpoint server("127.0.0.1:0");
  net::UdpEndpoint attacker("127.0.0.1:0");
  const std::string json_path = JsonPath("flood");
  RelayProcess relay({"--listen", "127.0.0.1:0", "--to", Address(server), "--max-datagram-bytes", "1000", "--delay-ms",
                      "5", "--jitter-ms", "2", "--duplicate", "0.1", "--reorder", "0.1", "--json", json_path});
  std::mt19937 rng(1234);
  std::vector<std::uint8_t> junk;
  std::size_t server_junk = 0;
  for (int i = 0; i < 4000; ++i) {
    // every size from empty to the largest UDP payload, some of them random bytes
    junk.resize(i % 4 == 0 ? rng() % 65508 : rng() % 1200);
    for (auto& b : junk) b = static_cast<std::uint8_t>(rng());
    attacker.SendTo(junk, i % 4 == 3 ? relay.upstream() : relay.listen());
    if (i % 100 == 0) {
      std::this_thread::sleep_for(2ms);  // let the socket buffers drain
      Drain(&server, &server_junk);
      Drain(&attacker);
    }
  }
  // after the flood it still relays
  constexpr int kSent = 100;
  std::set<std::uint64_t> indices;
  for (int i = 0; i < kSent; ++i) {
    ASSERT_TRUE(client.SendTo(Stamped(static_cast<std::uint64_t>(i), NowNs()), relay.listen()));
    std::this_thread::sleep_for(200us);
  }
  DrainUntilQuiet(500ms, [&] {
    const auto fresh = Drain(&server, &server_junk);
    for (const Arrival& a : fresh) indices.insert(a.index);
    return !fresh.empty();
  });
  EXPECT_EQ(indices.size(), static_cast<std::size_t>(kSent));
  EXPECT_GT(server_junk, 0u);  // garbage within the size limit is relayed too: the relay does not judge
  ASSERT_EQ(relay.Stop(SIGINT), 0) << relay.process().Stderr();
  const std::string json = testing::ReadFileOrEmpty(json_path);
  const std::string forward = Direction(json, "forward");
  EXPECT_GT(Dropped(forward, "oversize"), 100u);
  EXPECT_GE(Count(forward, "received"), static_cast<std::uint64_t>(kSent));
  ExpectBalanced(forward);
  ExpectBalanced(Direction(json, "back"));
}

}  // namespace
}  // namespace haptex
