// Accuracy in motion against cost (libs/textile/motion_accuracy.h): the four motions for four
// fabrics, meshes and steps of 1-50 ms under several solver settings, each against a converged
// reference of 0.1 ms steps on the same mesh. One row per run: the peak strain's error, the
// strain's largest error in time, the positions' RMS distance, the energy's largest distance
// and its growth after the release, and the median time per step with the solver's counts.
//
//   dynamic_accuracy [--meshes 21,41] [--steps-ms 1,2,5,10,20,50] [--fabrics light,heavy,stiff,denim]
//                    [--motions swing,push,push_whole,pinch] [--settings bw,default] [--csv FILE]
//                    [--reference-cache DIR]   (an existing folder: references kept, reference_cache.h)
//
// Accuracy does not depend on the machine; the time per step does (a quiet machine for it).
// After the rows, the trade: for each mesh, step and setting, its worst errors over the fabrics and
// motions run beside its cost (median time per step, CPU seconds per simulated second, solves and
// CG iterations per step), marked where another setting is both cheaper and better.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "bench/textile/accuracy_settings.h"
#include "bench/textile/reference_cache.h"
#include "libs/textile/motion_accuracy.h"
#include "libs/textile/validation.h"

namespace haptex::textile {
namespace {

constexpr double kSide_m = 0.2;
constexpr double kReferenceDt_s = 1e-4;

// One setting at one mesh and step, over every fabric and motion run: its worst errors and its cost.
struct Trade {
  double worst_peak_points = 0.0, worst_peak_pct = 0.0, worst_position_rms_mm = 0.0, worst_energy_pct = 0.0;
  std::string worst_peak_row;  // the motion and fabric of the worst peak
  std::vector<double> step_ms, solves, cg;
};

// Cost is the median step time per simulated second; a setting is dominated when another at the
// same mesh is no dearer and no worse in the peak's points and the positions, and better in one
// of them by more than 5 %.
void PrintTrades(const std::map<std::tuple<int, double, std::string>, Trade>& trades) {
  std::printf("\ntrade: worst over the fabrics and motions run, against cost\n");
  std::printf("%4s %5s %-16s %9s %9s %9s %8s %-22s %8s %9s %6s %6s %s\n", "mesh", "dt_ms", "setting", "peak_pts",
              "peak_%", "x_rms_mm", "E_err%", "worst peak at", "ms/step", "cpu_s/s", "solves", "cg", "");
  for (const auto& [key, t] : trades) {
    const auto& [mesh, dt_ms, setting] = key;
    const double ms = Median(t.step_ms);
    bool dominated = false;
    for (const auto& [other_key, o] : trades) {
      if (std::get<0>(other_key) != mesh || other_key == key) continue;
      const double other_ms = Median(o.step_ms) * dt_ms / std::get<1>(other_key);  // per 10 ms of motion alike
      // 5 % either way is a tie: step times on a shared host move that much run to run
      const bool no_worse = other_ms <= 1.05 * ms && o.worst_peak_points <= t.worst_peak_points &&
                            o.worst_position_rms_mm <= t.worst_position_rms_mm;
      const bool better = other_ms < 0.95 * ms || o.worst_peak_points < 0.95 * t.worst_peak_points ||
                          o.worst_position_rms_mm < 0.95 * t.worst_position_rms_mm;
      dominated = dominated || (no_worse && better);
    }
    std::printf("%4d %5g %-16s %9.4f %9.1f %9.2f %8.1f %-22s %8.3f %9.3f %6.2f %6.1f %s\n", mesh, dt_ms,
                setting.c_str(), t.worst_peak_points, t.worst_peak_pct, t.worst_position_rms_mm, t.worst_energy_pct,
                t.worst_peak_row.c_str(), ms, ms / dt_ms, Median(t.solves), Median(t.cg), dominated ? "dominated" : "");
  }
}

int Main(int argc, char** argv) {
  std::map<std::string, std::string> flags = {{"--meshes", "21,41"},
                                              {"--steps-ms", "1,2,5,10,20,50"},
                                              {"--fabrics", "light,heavy,stiff,denim"},
                                              {"--motions", "swing,push,pinch"},
                                              {"--settings", "bw,default"},
                                              {"--csv", ""},
                                              {"--reference-cache", ""}};
  for (int i = 1; i < argc; ++i) {
    const std::string flag = argv[i];
    if (!flags.count(flag) || i + 1 >= argc) {
      std::cerr << "usage: dynamic_accuracy [--meshes 21,41] [--steps-ms 1,2,5,10,20,50] [--fabrics "
                   "light,heavy,stiff,denim] [--motions swing,push,push_whole,pinch] [--settings bw,default,...] "
                   "[--csv FILE] [--reference-cache DIR]\n";
      return 2;
    }
    flags[flag] = argv[++i];
  }
  const auto settings = Settings();
  for (const std::string& name : Split(flags["--settings"])) {
    if (!settings.count(name)) throw std::invalid_argument("unknown setting '" + name + "'");
  }
  std::ofstream csv;
  if (!flags["--csv"].empty()) {
    csv.open(flags["--csv"]);
    csv << "motion,fabric,mesh,dt_ms,setting,peak_strain_ref_pct,peak_strain_err_pct,strain_in_time_err_pct,"
           "peak_strain_err_points,strain_in_time_err_points,"
           "position_rms_mm,energy_err_pct,energy_growth_pct,step_ms_median,newton_iterations,cg_iterations,"
           "halvings,newton_not_converged,nan_events\n";
  }
  // eps_err% and eps_t% relative to the reference's peak strain; eps_pts and eps_t_pts the same
  // errors in strain itself, in percentage points
  std::printf("%-6s %-6s %4s %5s %-16s %9s %8s %8s %8s %8s %8s %7s %7s %8s %6s %6s %5s %5s\n", "motion", "fabric",
              "mesh", "dt_ms", "setting", "peak_eps%", "eps_err%", "eps_t%", "eps_pts", "eps_t_pts", "x_rms_mm",
              "E_err%", "E_grow%", "ms/step", "newton", "cg", "halv", "nconv");
  std::map<std::tuple<int, double, std::string>, Trade> trades;
  for (const std::string& mesh_text : Split(flags["--meshes"])) {
    const int mesh = std::stoi(mesh_text);
    for (const std::string& fabric : Split(flags["--fabrics"])) {
      const FabricModel model = BuildFabricModel(FabricNamed(fabric), {kSide_m, kSide_m, mesh, mesh});
      const FabricState settled = validation::SettledHanging(model);
      for (const std::string& motion_name : Split(flags["--motions"])) {
        const validation::Motion motion =
            validation::MakeMotion(validation::MotionKindNamed(motion_name), model, settled);
        const std::string cached = flags["--reference-cache"].empty() ? std::string()
                                                                      : flags["--reference-cache"] + "/" + motion_name +
                                                                            "_" + fabric + "_" + mesh_text + ".ref";
        std::optional<validation::MotionTrace> read;
        if (!cached.empty()) read = ReadReference(cached, motion, kReferenceDt_s);
        const validation::MotionTrace ref =
            read ? *read : validation::RunMotion(motion, model, validation::ConvergedOptions(kReferenceDt_s));
        if (!cached.empty() && !read) WriteReference(cached, motion, ref);
        for (const std::string& dt_text : Split(flags["--steps-ms"])) {
          for (const std::string& setting : Split(flags["--settings"])) {
            StepOptions o = settings.at(setting);
            o.dt_s = std::stod(dt_text) * 1e-3;
            std::vector<double> step_ms;
            const validation::MotionTrace run =
                validation::RunMotion(motion, model, o, [&step_ms](FabricStepper& stepper, FabricState& s) {
                  const auto begin = std::chrono::steady_clock::now();
                  const StepResult r = stepper.Step(&s);
                  step_ms.push_back(
                      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - begin).count());
                  return r;
                });
            const double median_ms = Median(step_ms);
            const validation::MotionErrors e = validation::CompareMotion(motion, run, ref);
            const double peak_points = 100.0 * std::abs(run.peak_strain - ref.peak_strain);
            const double in_time_points = e.strain_in_time_pct * ref.peak_strain;
            std::printf(
                "%-6s %-6s %4d %5g %-16s %9.4f %8.2f %8.2f %8.4f %8.4f %8.3f %7.2f %7.2f %8.3f %6.2f %6.1f %5lld "
                "%5lld\n",
                motion_name.c_str(), fabric.c_str(), mesh, o.dt_s * 1e3, setting.c_str(), 100.0 * ref.peak_strain,
                e.peak_strain_pct, e.strain_in_time_pct, peak_points, in_time_points, e.position_rms_mm, e.energy_pct,
                e.energy_growth_pct, median_ms, run.newton_iterations_per_step, run.cg_iterations_per_step,
                static_cast<long long>(run.step_halvings), static_cast<long long>(run.newton_not_converged));
            std::fflush(stdout);
            Trade& trade = trades[{mesh, o.dt_s * 1e3, setting}];
            if (peak_points >= trade.worst_peak_points) trade.worst_peak_row = motion_name + " " + fabric;
            trade.worst_peak_points = std::max(trade.worst_peak_points, peak_points);
            trade.worst_peak_pct = std::max(trade.worst_peak_pct, e.peak_strain_pct);
            trade.worst_position_rms_mm = std::max(trade.worst_position_rms_mm, e.position_rms_mm);
            trade.worst_energy_pct = std::max(trade.worst_energy_pct, e.energy_pct);
            trade.step_ms.push_back(median_ms);
            trade.solves.push_back(run.newton_iterations_per_step);
            trade.cg.push_back(run.cg_iterations_per_step);
            if (csv.is_open()) {
              csv << motion_name << ',' << fabric << ',' << mesh << ',' << o.dt_s * 1e3 << ',' << setting << ','
                  << 100.0 * ref.peak_strain << ',' << e.peak_strain_pct << ',' << e.strain_in_time_pct << ','
                  << peak_points << ',' << in_time_points << ',' << e.position_rms_mm << ',' << e.energy_pct << ','
                  << e.energy_growth_pct << ',' << median_ms << ',' << run.newton_iterations_per_step << ','
                  << run.cg_iterations_per_step << ',' << run.step_halvings << ',' << run.newton_not_converged << ','
                  << run.nan_events << '\n';
              csv.flush();
            }
          }
        }
      }
    }
  }
  PrintTrades(trades);
  return 0;
}

}  // namespace
}  // namespace haptex::textile

int main(int argc, char** argv) {
  try {
    return haptex::textile::Main(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "dynamic_accuracy: " << e.what() << "\n";
    return 1;
  }
}
