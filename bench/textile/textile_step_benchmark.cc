// Time per step (dt = 10 ms unless stated) of a 20 x 20 cm fabric hanging from its stand, pushed by an
// alternating 1 N point load, for 21x21, 41x41 and 81x81 particles, with the default (implicit
// Euler, its guard on strain included) and the cheap (symplectic Euler, substeps from the stability
// estimate) integrators. Counters: the largest strain reached (peak_strain), the share of steps
// retaken in parts (split_steps) and their halvings.
// Plus the accuracy of each integrator on validation 1 (the paper's tensile test).
//
//   textile_step_benchmark --benchmark_repetitions=5 --benchmark_report_aggregates_only=true

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include <benchmark/benchmark.h>

#include "libs/scene/fabric_conversion.h"
#include "libs/textile/external_force.h"
#include "libs/textile/fabric_stepper.h"
#include "libs/textile/fabric_strain.h"
#include "libs/textile/kes_material.h"
#include "libs/textile/validation.h"

namespace haptex::textile {
namespace {

// Third benchmark argument: 0 = stiff woven, 1 = soft knit.
const char* kFabrics[] = {"wang2011_black_denim_11oz", "wang2011_navy_sparkle_sweat"};

Placement HangingPlacement() {
  Placement pl;
  pl.axis_u_W = Eigen::Vector3d(0, 0, -1);
  pl.axis_v_W = Eigen::Vector3d(1, 0, 0);
  return pl;
}

// The step's split on strain, where not the default's guard (a bound of 0: never split).
struct StrainSplit {
  double bound = 0.0;
  int max_halvings = 0;
};

void BM_Step(benchmark::State& bm, Integrator method, Preconditioner preconditioner,
             std::optional<StrainSplit> split = std::nullopt) {
  const int n = static_cast<int>(bm.range(0));
  const FabricModel model =
      BuildFabricModel(MaterialFromKes(scene::LoadKesFabric(kFabrics[bm.range(2)])), {0.2, 0.2, n, n});
  FabricState s = MakeRestState(model, HangingPlacement());
  for (int p : validation::WarpRow(model, 0)) s.Fix(p);
  StepOptions opt;
  opt.method = method;
  if (method == Integrator::kBdf2) opt.newton_max_iterations = 8;  // it needs them (step_options.h)
  opt.preconditioner = preconditioner;
  opt.dt_s = 1e-6 * static_cast<double>(bm.range(3));
  if (bm.range(1) > 0) opt.cg_tolerance = 1.0 / static_cast<double>(bm.range(1));
  opt.max_substeps = 20000;
  if (split) {
    opt.max_step_halvings = split->max_halvings;
    opt.max_strain_rise_per_step = split->bound;
  }
  std::unique_ptr<FabricStepper> stepper;
  try {
    stepper = std::make_unique<FabricStepper>(model, opt);
  } catch (const std::invalid_argument& e) {
    bm.SkipWithError(e.what());
    return;
  }
  const int centre = model.mesh.Index(n / 2, n / 2);
  // Warm-up: let it fall and hang.
  for (int i = 0; i < 20; ++i) stepper->Step(&s);
  long step = 0;
  double cg_iterations = 0.0, fallbacks = 0.0, split_steps = 0.0, peak_strain = 0.0;
  // Alternating push, so the fabric keeps moving (a finger, roughly).
  auto load = [&] { SetPointLoad(centre, Eigen::Vector3d(0, (step / 25) % 2 ? 1.0 : -1.0, 0), &s); };
  for (auto _ : bm) {
    load();
    const StepResult r = stepper->Step(&s);
    cg_iterations += r.cg.iterations;
    fallbacks += r.cg.preconditioner_fallback ? 1.0 : 0.0;
    split_steps += r.step_halvings > 0 ? 1.0 : 0.0;
    ++step;
  }
  const auto timed_halvings = static_cast<double>(s.diagnostics.step_halvings);
  // The largest strain over two more load periods, untimed (pausing the timer every step costs
  // more than the strain itself and would distort the time).
  for (int i = 0; i < 50; ++i, ++step) {
    load();
    stepper->Step(&s);
    peak_strain = std::max(peak_strain, LargestTensileStrain(model, s.x_W_m));
  }
  bm.counters["particles"] = model.num_particles;
  bm.counters["substeps"] = stepper->substeps();
  bm.counters["cg_iters"] = benchmark::Counter(cg_iterations, benchmark::Counter::kAvgIterations);
  bm.counters["nan_events"] = static_cast<double>(s.diagnostics.nan_events);
  bm.counters["pc_fallbacks"] = fallbacks;
  bm.counters["halvings"] = timed_halvings;
  bm.counters["peak_strain"] = peak_strain;
  bm.counters["split_steps"] = benchmark::Counter(split_steps, benchmark::Counter::kAvgIterations);
}

// Args: particles per side, 1 / CG tolerance (0: default), fabric, dt [us].
void BM_StepImplicitMultilevel(benchmark::State& bm) {
  BM_Step(bm, Integrator::kImplicitEuler, Preconditioner::kMultilevel);
}
void BM_StepImplicitJacobi(benchmark::State& bm) {
  BM_Step(bm, Integrator::kImplicitEuler, Preconditioner::kBlockJacobi);
}
void BM_StepSymplectic(benchmark::State& bm) {
  BM_Step(bm, Integrator::kSymplecticEuler, Preconditioner::kBlockJacobi);
}
void BM_StepBdf2Multilevel(benchmark::State& bm) { BM_Step(bm, Integrator::kBdf2, Preconditioner::kMultilevel); }
// dynamic_accuracy's bw_strain_split: a point of strain a step, down to a sixteenth
void BM_StepImplicitStrainSplit(benchmark::State& bm) {
  BM_Step(bm, Integrator::kImplicitEuler, Preconditioner::kMultilevel, StrainSplit{0.01, 4});
}
// the single linearised step never retaken (the default before the guard)
void BM_StepImplicitUnguarded(benchmark::State& bm) {
  BM_Step(bm, Integrator::kImplicitEuler, Preconditioner::kMultilevel, StrainSplit{0.0, 0});
}
BENCHMARK(BM_StepImplicitMultilevel)
    ->ArgsProduct({{21, 41, 81}, {1000, 100}, {0, 1}, {10000}})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StepBdf2Multilevel)->ArgsProduct({{21, 41}, {0}, {0, 1}, {10000}})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StepImplicitStrainSplit)->ArgsProduct({{21, 41}, {0}, {0, 1}, {10000}})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StepImplicitUnguarded)->ArgsProduct({{21, 41, 81}, {0}, {0, 1}, {10000}})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StepImplicitJacobi)->ArgsProduct({{21, 41, 81}, {1000, 100}, {0}, {10000}})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StepSymplectic)->ArgsProduct({{21, 41, 81}, {0}, {0, 1}, {10000}})->Unit(benchmark::kMillisecond);
// The local-patch regime (1 kHz, small patch): where the cheap integrator pays off.
BENCHMARK(BM_StepImplicitMultilevel)->Args({11, 0, 1, 1000})->Args({21, 0, 1, 1000})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StepSymplectic)->Args({11, 0, 1, 1000})->Args({21, 0, 1, 1000})->Unit(benchmark::kMillisecond);

// Validation 1 with each integrator: static elongation of the 20 x 38 cm strip (448 triangles)
// under 2.4 N plus self-weight, relative error against the analytic integral.
void BM_TensileAccuracy(benchmark::State& bm, Integrator method) {
  const FabricMaterial material = MaterialFromKes(validation::CompositeDenim());
  const FabricModel model = BuildFabricModel(material, {0.38, 0.2, 17, 15});
  double rel = 0.0, steps = 0.0, substeps = 0.0;
  for (auto _ : bm) {
    FabricState s = MakeRestState(model, HangingPlacement());
    for (int p : validation::WarpRow(model, 0)) s.Fix(p);
    const auto bottom = validation::WarpRow(model, 16);
    AddEdgeLoad(model, bottom, Eigen::Vector3d(0, 0, -2.4), &s);
    StepOptions opt;
    opt.method = method;
    opt.dt_s = 0.01;
    opt.max_substeps = 20000;
    std::unique_ptr<FabricStepper> stepper;
    try {
      stepper = std::make_unique<FabricStepper>(model, opt);
    } catch (const std::invalid_argument& e) {
      bm.SkipWithError(e.what());
      return;
    }
    substeps = stepper->substeps();
    steps = validation::RunToRest(stepper.get(), &s, 3000, 1e-6);
    double z = 0.0;
    for (int p : bottom) z += s.x(p).z();
    const double simulated = -z / static_cast<double>(bottom.size()) - 0.38;
    const double exact =
        validation::AnalyticHangingElongation(material.tensile_warp, 0.38, 0.2, material.density_kg_per_m2, 2.4, 9.81);
    rel = std::abs(simulated - exact) / exact;
  }
  bm.counters["rel_error_pct"] = 100.0 * rel;
  bm.counters["steps_to_rest"] = steps;
  bm.counters["substeps"] = substeps;
}

void BM_TensileAccuracyImplicit(benchmark::State& bm) { BM_TensileAccuracy(bm, Integrator::kImplicitEuler); }
void BM_TensileAccuracySymplectic(benchmark::State& bm) { BM_TensileAccuracy(bm, Integrator::kSymplecticEuler); }
BENCHMARK(BM_TensileAccuracyImplicit)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TensileAccuracySymplectic)->Iterations(1)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace haptex::textile

BENCHMARK_MAIN();
