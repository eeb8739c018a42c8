// Pauses of the host against a held contact, in one process (services/in_process): for each scene,
// each paused service (and all of them at once) and each pause length, the force each finger held
// before, its peak after against the resume bound (max(1.1 x held, held + 0.3 N)), the time until
// the pinch holds again, the largest sign reversal of a force component within 10 ms, and what the
// bridge and the controller counted. Deterministic: a setting gives the same row every run.
//
//   build/bench/stall/stall_sweep [--case NAME=SCENE@AT_S ...] [--pause-ms MS ...] [--target T ...]
//       [--watch-s S] [--trace-dir DIR]
//
// T: mock_grab, device_bridge, local_contact, global_sim, all. Without --case: the pinch
// (pinch_stretch at 4.5 s), the rub (rub_friction at 3.0 s) and the fold (fold at 5.5 s, holding the folded cloth).

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "libs/flags/finite_number.h"
#include "libs/scene/scene_loader.h"
#include "services/in_process/stall_response.h"

namespace {

namespace ip = haptex::in_process;

struct Case {
  std::string name, scene_path;
  double at_s = 0.0;
};

const std::map<std::string, ip::StallTarget>& Targets() {
  static const std::map<std::string, ip::StallTarget> targets{{"mock_grab", ip::StallTarget::kMockGrab},
                                                              {"device_bridge", ip::StallTarget::kDeviceBridge},
                                                              {"local_contact", ip::StallTarget::kLocalContact},
                                                              {"global_sim", ip::StallTarget::kGlobalSim},
                                                              {"all", ip::StallTarget::kAll}};
  return targets;
}

bool ParseCase(const std::string& text, Case* c) {
  const auto eq = text.find('='), at = text.rfind('@');
  if (eq == std::string::npos || at == std::string::npos || at < eq) return false;
  c->name = text.substr(0, eq);
  c->scene_path = text.substr(eq + 1, at - eq - 1);
  try {
    std::size_t used = 0;
    c->at_s = std::stod(text.substr(at + 1), &used);
    return used == text.size() - at - 1 && std::isfinite(c->at_s) && c->at_s > 0.2;
  } catch (const std::exception&) {
    return false;
  }
}

}  // namespace

int main(int argc, char** argv) {
  const std::string root = HAPTEX_SOURCE_DIR;
  std::vector<std::string> case_texts{"pinch=" + root + "/launch/scenes/pinch_stretch.textproto@4.5",
                                      "rub=" + root + "/launch/scenes/rub_friction.textproto@3.0",
                                      "fold=" + root + "/launch/scenes/fold.textproto@5.5"};
  std::vector<double> pauses_ms{0, 2, 5, 10, 30, 100};
  std::vector<std::string> target_names{"mock_grab", "device_bridge", "local_contact", "global_sim", "all"};
  std::string trace_dir;
  double watch_s = ip::StallResponseOptions{}.watch_after_s;
  CLI::App app{"Pauses of the host against a held contact, every service loop in one process"};
  app.add_option("--case", case_texts, "NAME=SCENE@AT_S: the stall starts AT_S into SCENE (repeat the flag)");
  app.add_option("--pause-ms", pauses_ms, "pause lengths [ms] (repeat the flag; 0: no pause, the reference)")
      ->check(CLI::Range(0.0, 10000.0));
  app.add_option("--target", target_names, "what pauses (repeat the flag)")
      ->check(CLI::IsMember({"mock_grab", "device_bridge", "local_contact", "global_sim", "all"}));
  app.add_option("--watch-s", watch_s, "how long after a stall's end its response is watched [s]")
      ->check(CLI::Range(0.01, 60.0));
  app.add_option("--trace-dir", trace_dir, "write each setting's force trace here as CSV");
  haptex::flags::RefuseNonFiniteNumbers(app);
  CLI11_PARSE(app, argc, argv);

  std::printf(
      "| case | paused | ms | held N (thumb/index) | peak after / bound | time to hold again ms | largest reversal N "
      "| cuts: gap disarms / gaps held / stale models / host timeouts / device lost |\n"
      "|---|---|---|---|---|---|---|---|\n");
  for (const std::string& text : case_texts) {
    Case c;
    if (!ParseCase(text, &c)) {
      std::fprintf(stderr, "--case %s: expected NAME=SCENE@AT_S with AT_S > 0.2 s\n", text.c_str());
      return 2;
    }
    haptex::scene::LoadedScene scene;
    try {
      scene = haptex::scene::LoadScene(
          c.scene_path, haptex::scene::FabricDatabase(haptex::scene::FabricDatabase::DefaultDirectory()));
    } catch (const std::exception& e) {
      std::fprintf(stderr, "%s\n", e.what());
      return 2;
    }
    for (const std::string& target : target_names) {
      for (const double pause_ms : pauses_ms) {
        const ip::Stall stall{Targets().at(target), c.at_s, pause_ms / 1e3};
        std::vector<ip::StallTraceSample> trace;
        ip::StallResponseOptions options;
        options.watch_after_s = watch_s;
        const ip::StallResponse r = ip::MeasureStall(scene, stall, options, trace_dir.empty() ? nullptr : &trace);
        const auto& f = r.fingers;
        char held_again[32];
        if (std::isfinite(r.held_again_after_s)) {
          std::snprintf(held_again, sizeof held_again, "%.1f", r.held_again_after_s * 1e3);
        } else {
          if (r.state_before != haptex::contact::ContactState::kI) {
            std::snprintf(held_again, sizeof held_again, "not in %g s", watch_s);
          } else {
            std::snprintf(held_again, sizeof held_again, "(no contact)");
          }
        }
        std::printf(
            "| %s | %s | %g | %.2f / %.2f | %.2f | %s | %.2f | %llu / %llu / %llu / %llu / %llu |\n", c.name.c_str(),
            target.c_str(), pause_ms, f[0].held_N, f[1].held_N, r.worst_peak_over_bound, held_again,
            std::max(f[0].largest_reversal_N, f[1].largest_reversal_N),
            static_cast<unsigned long long>(r.tick_gap_disarms), static_cast<unsigned long long>(r.tick_gaps_held),
            static_cast<unsigned long long>(r.stale_model_cuts), static_cast<unsigned long long>(r.host_timeouts),
            static_cast<unsigned long long>(r.device_lost_events));
        std::fflush(stdout);
        if (!trace_dir.empty()) {
          std::ofstream csv(trace_dir + "/" + c.name + "_" + target + "_" + std::to_string(static_cast<int>(pause_ms)) +
                            "ms.csv");
          csv << "t_s,state,thumb_fx,thumb_fy,thumb_fz,index_fx,index_fy,index_fz,thumb_x,thumb_y,thumb_z,index_x,"
                 "index_y,index_z\n";
          for (const ip::StallTraceSample& s : trace) {
            csv << s.t_s << ',' << static_cast<int>(s.state);
            for (const auto& v : s.commanded_N) csv << ',' << v.x() << ',' << v.y() << ',' << v.z();
            for (const auto& v : s.position_m) csv << ',' << v.x() << ',' << v.y() << ',' << v.z();
            csv << '\n';
          }
        }
      }
    }
  }
  return 0;
}
