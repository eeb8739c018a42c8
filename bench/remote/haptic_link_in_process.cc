// The haptic link under delay and loss, in one process (services/in_process): a scene's mock user
// through the real loop objects with simulated links. Prints, per setting, the commanded force's
// peak and its spread in the window (pinch_stretch's hold by default), the force error there against
// the first setting (normally 0 ms, no loss) in % of that setting's peak, and the energy the device
// put into the fingers. Deterministic: the error is the link's alone, where between real processes
// two runs of one setting already differ by the host's scheduling.
//
//   build/bench/remote/haptic_link_in_process SCENE [--seconds S] [--rtt-ms R ...] [--loss L ...]
//       [--placement haptic|global] [--window-from S --window-to S] [--csv FILE]

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "libs/flags/finite_number.h"
#include "libs/scene/scene_loader.h"
#include "services/in_process/in_process_system.h"

namespace {

using haptex::in_process::InProcessSystem;
using haptex::in_process::LinkImpairments;

struct Result {
  double peak_N = 0, hold_mean_N = 0, hold_sd_N = 0, energy_J = 0, max_step_N = 0;
  std::uint64_t damped_ticks = 0, too_old = 0;
  std::vector<double> window_N;  ///< each finger's commanded force, every tick of the window
};

struct Window {
  double from_s = 4.0, to_s = 5.0;
};

Result Run(const haptex::scene::LoadedScene& scene, double seconds, double rtt_ms, double loss, bool haptic,
           const Window& window, std::ofstream* csv) {
  haptex::netsim::ImpairmentConfig each_way;
  each_way.delay_ms = rtt_ms / 2;
  each_way.jitter_ms = rtt_ms > 0 ? 1.0 : 0.0;
  each_way.loss = loss;
  InProcessSystem system(scene, haptic ? LinkImpairments::HapticLink(each_way) : LinkImpairments::GlobalLink(each_way));
  Result r;
  double sum = 0, sum2 = 0;
  int n = 0;
  double previous = 0;
  for (int k = 0; system.t_s() < seconds; ++k) {
    system.Step();
    const double f = std::max(system.finger(0).commanded_N.norm(), system.finger(1).commanded_N.norm());
    r.peak_N = std::max(r.peak_N, f);
    r.max_step_N = std::max(r.max_step_N, std::abs(f - previous));
    previous = f;
    if (system.t_s() > window.from_s && system.t_s() < window.to_s) {
      sum += f;
      sum2 += f * f;
      ++n;
      r.window_N.push_back(system.finger(0).commanded_N.norm());
      r.window_N.push_back(system.finger(1).commanded_N.norm());
    }
    if (csv != nullptr && k % 5 == 0) {
      const auto& m = system.bridge().bridge().force_model(haptex::device::Manipulator::kIndex);
      const auto& st = system.bridge().bridge().finger_state(haptex::device::Manipulator::kIndex);
      *csv << rtt_ms << ',' << loss << ',' << system.t_s() << ',' << system.finger(0).commanded_N.norm() << ','
           << system.finger(1).commanded_N.norm() << ',' << system.finger(0).position_m.y() << ','
           << system.finger(1).position_m.y() << ',' << m.force0_W_N.norm() << ',' << m.stiffness_W_N_per_m.norm()
           << ',' << (st.p_pred_W_m - m.x0_W_m).norm() << '\n';
    }
  }
  r.hold_mean_N = n > 0 ? sum / n : 0;
  r.hold_sd_N = n > 0 ? std::sqrt(std::max(0.0, sum2 / n - r.hold_mean_N * r.hold_mean_N)) : 0;
  r.energy_J = system.energy_into_finger_J(0) + system.energy_into_finger_J(1);
  for (int f = 0; f < 2; ++f) {
    r.damped_ticks +=
        system.bridge().bridge().passivity(static_cast<haptex::device::Manipulator>(f)).counters().damped_steps;
  }
  r.too_old = system.bridge().bridge().counters().slow_link_ticks;
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  std::string scene_path, csv_path, placement = "haptic";
  double seconds = 8;
  Window window;
  std::vector<double> rtts{0, 10, 20, 50, 100, 200}, losses{0};
  CLI::App app{"The haptic link under delay and loss, every service loop in one process"};
  app.add_option("scene", scene_path, "the scene")->required()->check(CLI::ExistingFile);
  app.add_option("--seconds", seconds, "simulated seconds per setting")->check(CLI::Range(0.1, 600.0));
  app.add_option("--rtt-ms", rtts, "round trips [ms] (repeat the flag)")->check(CLI::Range(0.0, 1000.0));
  app.add_option("--loss", losses, "loss each way (repeat the flag)")->check(CLI::Range(0.0, 1.0));
  app.add_option("--placement", placement, "haptic: bridge | simulation; global: global_sim far")
      ->check(CLI::IsMember({"haptic", "global"}));
  app.add_option("--window-from", window.from_s, "the window's start [s] (pinch_stretch's hold: 4)");
  app.add_option("--window-to", window.to_s, "the window's end [s] (5)");
  app.add_option("--csv", csv_path, "also write a trace here");
  haptex::flags::RefuseNonFiniteNumbers(app);
  CLI11_PARSE(app, argc, argv);
  const bool haptic = placement == "haptic";
  haptex::scene::LoadedScene scene;
  try {
    scene = haptex::scene::LoadScene(scene_path,
                                     haptex::scene::FabricDatabase(haptex::scene::FabricDatabase::DefaultDirectory()));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
  std::ofstream csv;
  if (!csv_path.empty()) csv.open(csv_path);
  if (!(window.to_s > window.from_s)) {
    std::fprintf(stderr, "--window-to must be after --window-from\n");
    return 2;
  }
  std::printf("rtt_ms loss peak_N win_mean_N win_sd_N error_pct max_step_N energy_J damped_ticks slow_link_ticks\n");
  Result reference;
  bool first = true;
  for (double loss : losses) {
    for (double rtt : rtts) {
      const Result r = Run(scene, seconds, rtt, loss, haptic, window, csv.is_open() ? &csv : nullptr);
      if (first) reference = r;
      first = false;
      // RMS over the window's ticks and both fingers, in % of the first setting's peak
      const std::size_t n = std::min(r.window_N.size(), reference.window_N.size());
      double e2 = 0;
      for (std::size_t i = 0; i < n; ++i) e2 += std::pow(r.window_N[i] - reference.window_N[i], 2);
      const double error_pct =
          n > 0 && reference.peak_N > 0 ? 100.0 * std::sqrt(e2 / static_cast<double>(n)) / reference.peak_N : 0.0;
      std::printf("%6.0f %4.2f %6.2f %6.3f %6.3f %6.1f %6.3f %8.4f %8llu %8llu\n", rtt, loss, r.peak_N, r.hold_mean_N,
                  r.hold_sd_N, error_pct, r.max_step_N, r.energy_J, static_cast<unsigned long long>(r.damped_ticks),
                  static_cast<unsigned long long>(r.too_old));
      std::fflush(stdout);
    }
  }
  return 0;
}
