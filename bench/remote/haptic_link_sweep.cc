// The haptic link under delay and loss through the real processes: for each round trip and loss,
// `haptex launch SCENE --impair ...` puts the links that would cross the network through relays,
// then the run's force log (what the mock's fingers felt) and summary.json (what the services
// counted) give one row: the force the pinch held and how steadily, the energy the device put into
// the fingers, dropouts and watchdog events, the link's round trip and the bridge's reactions.
//
//   build/bench/remote/haptic_link_sweep --haptex build/cli/haptex --scene launch/scenes/pinch_stretch.textproto
//       --out runs/sweep [--placement haptic|global] [--rtt-ms 0,10,...] [--loss 0,0.05,...]
//       [--jitter-ms 2] [--duration 8] [--hold-from 4 --hold-to 5] [--rt-priority P] [--csv FILE]
//
// "haptic": the device and its bridge here, local_contact and global_sim far (the bridge's links to
// both impaired). "global": the bridge and local_contact here, global_sim far (global_sim's links to
// both impaired). The first setting (normally 0 ms, no loss) is the reference of the force error.
// Run it alone on the machine: the services are real-time processes.

#include <google/protobuf/struct.pb.h>
#include <google/protobuf/util/json_util.h>
#include <signal.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "launch/child_process.h"
#include "launch/force_log_reader.h"
#include "libs/flags/finite_number.h"

namespace {

namespace fs = std::filesystem;
using google::protobuf::Struct;
using google::protobuf::Value;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct Options {
  std::string haptex, scene, out, placement = "haptic", csv;
  std::vector<double> rtt_ms{0, 10, 20, 50, 100, 200}, loss{0, 0.01, 0.05, 0.10};
  double jitter_ms = 2.0, duration_s = 8.0, hold_from_s = 4.0, hold_to_s = 5.0;
  int rt_priority = 0;
};

struct Row {
  double rtt_ms = 0, loss = 0;
  bool ran = false;
  double peak_N = 0, hold_mean_N = 0, hold_sd_N = 0, hold_min_N = 0, hold_max_N = 0, error_rms_N = 0;
  double energy_J = 0;
  int dropouts = 0, host_timeout_events = 0;
  double round_trip_p50_ms = kNaN, end_to_end_p99_ms = kNaN, bridge_rate_hz = kNaN;
  double slow_link_events = kNaN, damped_ticks = kNaN, tick_gap_disarms = kNaN, stale_states_ticks = kNaN;
  std::vector<double> hold_N;  // the hold window's forces, for the error against the reference
};

const Value* Find(const Struct& s, const std::string& key) {
  const auto it = s.fields().find(key);
  return it == s.fields().end() ? nullptr : &it->second;
}

double Number(const Struct& s, std::initializer_list<const char*> path) {
  const Struct* at = &s;
  const Value* v = nullptr;
  for (const char* key : path) {
    if (at == nullptr || (v = Find(*at, key)) == nullptr) return kNaN;
    at = v->has_struct_value() ? &v->struct_value() : nullptr;
  }
  return v != nullptr && v->has_number_value() ? v->number_value() : kNaN;
}

const Struct* Service(const Struct& summary, const std::string& name) {
  const Value* services = Find(summary, "services");
  if (services == nullptr || !services->has_list_value()) return nullptr;
  for (const Value& s : services->list_value().values()) {
    const Value* n = s.has_struct_value() ? Find(s.struct_value(), "name") : nullptr;
    if (n != nullptr && n->string_value() == name) return &s.struct_value();
  }
  return nullptr;
}

std::string Impairment(double rtt_ms, double jitter_ms, double loss, int seed) {
  std::ostringstream s;
  s << "rtt_ms=" << rtt_ms << ",jitter_ms=" << (rtt_ms > 0 ? jitter_ms : 0.0) << ",loss=" << loss << ",seed=" << seed;
  return s.str();
}

bool RunOne(const Options& o, Row* row) {
  std::ostringstream name;
  name << o.placement << "_rtt" << row->rtt_ms << "_loss" << row->loss;
  const std::string dir = o.out + "/" + name.str();
  fs::remove_all(dir);
  fs::create_directories(o.out);
  std::vector<std::string> argv{o.haptex,     "launch", o.scene, "--duration", std::to_string(o.duration_s),
                                "--no-plots", "--out",  dir};
  if (o.rt_priority > 0) argv.insert(argv.end(), {"--rt-priority", std::to_string(o.rt_priority)});
  if (row->rtt_ms > 0 || row->loss > 0) {
    const bool haptic = o.placement == "haptic";
    const std::string far_a = haptic ? "device_bridge-local_contact" : "global_sim-local_contact";
    const std::string far_b = haptic ? "device_bridge-global_sim" : "global_sim-device_bridge";
    argv.insert(argv.end(), {"--impair", far_a + ":" + Impairment(row->rtt_ms, o.jitter_ms, row->loss, 1), "--impair",
                             far_b + ":" + Impairment(row->rtt_ms, o.jitter_ms, row->loss, 3)});
  }
  std::vector<std::string> env;
  for (char** e = environ; *e != nullptr; ++e) env.emplace_back(*e);
  haptex::launch::ChildProcess launch(argv, env, o.out + "/" + name.str() + ".log");
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::duration<double>(o.duration_s + 60.0);
  while (!launch.Poll()) {
    if (std::chrono::steady_clock::now() > give_up) {
      launch.Signal(SIGINT);
      std::this_thread::sleep_for(std::chrono::seconds(5));
      std::cerr << name.str() << ": the run did not end\n";
      return false;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  if (launch.exit_text() != "exit 0") std::cerr << name.str() << ": haptex launch " << launch.exit_text() << "\n";

  const auto rows = haptex::launch::ReadForceLogRows(dir + "/mock_grab_forces.csv");
  if (rows.size() < 2) {
    std::cerr << name.str() << ": no force log\n";
    return false;
  }
  const double t0_ns = static_cast<double>(rows.front().time_ns);
  double sum = 0, sum2 = 0;
  bool was_timed_out = false, holding = false;
  row->hold_min_N = 1e9;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto& r = rows[i];
    const double t_s = (static_cast<double>(r.time_ns) - t0_ns) * 1e-9;
    const double f = std::max(r.CommandedNormN(0), r.CommandedNormN(1));
    row->peak_N = std::max(row->peak_N, f);
    if (r.host_timed_out && !was_timed_out) ++row->host_timeout_events;
    was_timed_out = r.host_timed_out;
    if (i + 1 < rows.size()) {
      for (std::size_t finger = 0; finger < 2; ++finger) {
        for (std::size_t k = 0; k < 3; ++k) {
          row->energy_J += r.applied_D_N[finger][k] * (rows[i + 1].position_D_m[finger][k] - r.position_D_m[finger][k]);
        }
      }
    }
    if (t_s >= o.hold_from_s && t_s <= o.hold_to_s) {
      row->hold_N.push_back(f);
      sum += f;
      sum2 += f * f;
      row->hold_min_N = std::min(row->hold_min_N, f);
      row->hold_max_N = std::max(row->hold_max_N, f);
      // a dropout: the held force falls below half of its window's start and is counted once
      const bool low = f < 0.5 * row->hold_N.front();
      if (low && holding) ++row->dropouts;
      holding = !low;
    }
  }
  const double n = static_cast<double>(row->hold_N.size());
  if (n > 0) {
    row->hold_mean_N = sum / n;
    row->hold_sd_N = std::sqrt(std::max(0.0, sum2 / n - row->hold_mean_N * row->hold_mean_N));
  }

  std::ifstream in(dir + "/summary.json");
  std::stringstream text;
  text << in.rdbuf();
  Struct summary;
  if (google::protobuf::util::JsonStringToMessage(text.str(), &summary).ok()) {
    if (const Struct* bridge = Service(summary, "device_bridge")) {
      row->round_trip_p50_ms = Number(*bridge, {"latencies", "haptic_round_trip", "p50_us"}) * 1e-3;
      row->end_to_end_p99_ms = Number(*bridge, {"latencies", "motion_to_force_end_to_end", "p99_us"}) * 1e-3;
      row->slow_link_events = Number(*bridge, {"counters", "slow_link_events"});
      row->damped_ticks = Number(*bridge, {"counters", "passivity_damped_ticks"});
      row->tick_gap_disarms = Number(*bridge, {"counters", "tick_gap_disarms"});
      const Value* loops = Find(*bridge, "loops");
      if (loops != nullptr && loops->list_value().values_size() > 0) {
        row->bridge_rate_hz = Number(loops->list_value().values(0).struct_value(), {"rate_hz"});
      }
    }
    if (const Struct* local = Service(summary, "local_contact")) {
      row->stale_states_ticks = Number(*local, {"counters", "stale_finger_states_ticks"});
    }
  }
  row->ran = true;
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{"The haptic link under delay and loss, through the real processes and haptex relay"};
  app.add_option("--haptex", o.haptex, "the haptex executable")->required()->check(CLI::ExistingFile);
  app.add_option("--scene", o.scene, "the scene to launch")->required()->check(CLI::ExistingFile);
  app.add_option("--out", o.out, "folder for the runs")->required();
  app.add_option("--placement", o.placement, "haptic: the simulation far; global: global_sim far")
      ->check(CLI::IsMember({"haptic", "global"}));
  app.add_option("--rtt-ms", o.rtt_ms, "round trips [ms]")->delimiter(',')->check(CLI::Range(0.0, 1000.0));
  app.add_option("--loss", o.loss, "loss probabilities, each way")->delimiter(',')->check(CLI::Range(0.0, 1.0));
  app.add_option("--jitter-ms", o.jitter_ms, "jitter each way [ms]")->check(CLI::Range(0.0, 100.0));
  app.add_option("--duration", o.duration_s, "seconds per run")->check(CLI::Range(1.0, 600.0));
  app.add_option("--hold-from", o.hold_from_s, "the hold window's start after the first force log row [s]");
  app.add_option("--hold-to", o.hold_to_s, "the hold window's end [s]");
  app.add_option("--csv", o.csv, "also write the table here");
  app.add_option("--rt-priority", o.rt_priority, "haptex launch --rt-priority (0: normal scheduling)")
      ->check(CLI::Range(0, 99));
  haptex::flags::RefuseNonFiniteNumbers(app);
  CLI11_PARSE(app, argc, argv);

  std::vector<Row> rows;
  for (double loss : o.loss) {
    for (double rtt : o.rtt_ms) {
      Row row;
      row.rtt_ms = rtt;
      row.loss = loss;
      RunOne(o, &row);
      rows.push_back(row);
      std::fprintf(stderr, "%s rtt %g ms loss %g: hold %.3f +- %.3f N\n", o.placement.c_str(), rtt, loss,
                   row.hold_mean_N, row.hold_sd_N);
    }
  }
  // the force error against the reference's hold, sample by sample from the window's start
  const Row& ref = rows.front();
  for (Row& r : rows) {
    const std::size_t n = std::min(r.hold_N.size(), ref.hold_N.size());
    double e2 = 0;
    for (std::size_t i = 0; i < n; ++i) e2 += (r.hold_N[i] - ref.hold_N[i]) * (r.hold_N[i] - ref.hold_N[i]);
    r.error_rms_N = n > 0 ? std::sqrt(e2 / static_cast<double>(n)) : kNaN;
  }
  std::ofstream csv;
  if (!o.csv.empty()) csv.open(o.csv);
  const char* header =
      "placement,rtt_ms,loss,ran,peak_N,hold_mean_N,hold_sd_N,hold_min_N,hold_max_N,error_rms_N,energy_mJ,dropouts,"
      "host_timeouts,round_trip_p50_ms,end_to_end_p99_ms,bridge_rate_hz,slow_link_events,passivity_damped_ticks,"
      "tick_gap_disarms,stale_finger_states_ticks";
  std::printf("%s\n", header);
  if (csv.is_open()) csv << header << '\n';
  for (const Row& r : rows) {
    char line[512];
    std::snprintf(line, sizeof line,
                  "%s,%g,%g,%d,%.2f,%.3f,%.3f,%.3f,%.3f,%.3f,%.2f,%d,%d,%.1f,%.1f,%.0f,%.0f,%.0f,%.0f,%.0f",
                  o.placement.c_str(), r.rtt_ms, r.loss, r.ran ? 1 : 0, r.peak_N, r.hold_mean_N, r.hold_sd_N,
                  r.hold_min_N, r.hold_max_N, r.error_rms_N, r.energy_J * 1e3, r.dropouts, r.host_timeout_events,
                  r.round_trip_p50_ms, r.end_to_end_p99_ms, r.bridge_rate_hz, r.slow_link_events, r.damped_ticks,
                  r.tick_gap_disarms, r.stale_states_ticks);
    std::printf("%s\n", line);
    if (csv.is_open()) csv << line << '\n';
  }
  return 0;
}
