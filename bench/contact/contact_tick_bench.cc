// One haptic tick of a local patch (contact update + one fabric step): the cost that decides
// whether local_contact reaches 1-5 kHz. Reports the mean (Google Benchmark) and the per-tick
// median and p99 as counters p50_us / p99_us.
//
//   build/bench/contact/contact_tick_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <utility>
#include <vector>

#include <benchmark/benchmark.h>

#include "libs/contact/finger_geometry.h"
#include "libs/contact/haptic_step_options.h"
#include "libs/contact/patch_simulation.h"
#include "libs/scene/fabric_conversion.h"
#include "libs/textile/fabric_model.h"
#include "libs/textile/kes_material.h"

namespace haptex::contact {
namespace {

using V = Eigen::Vector3d;

FingerPose Facing(const V& centre, const V& pad_normal) { return PoseFacing(centre, pad_normal, V::UnitX()); }

// 20 x 20 = 400 particles over 2 x 2 cm (about 1 mm spacing), border fixed, lying at z = 0,
// stepped at 1 ms. Solver config 0: block-Jacobi PCG to 1e-3 (the tests' tight solve); 1:
// block Jacobi to 1e-2, at most 20 iterations (the baseline of the accuracy table); 2: multilevel
// PCG to 1e-2; 3: local_contact's haptic step (HapticPatchStepOptions: Gauss-Seidel); 4: the
// same at 0.2 ms, as local_contact steps at 5 kHz; 9: block Jacobi to 1e-9, the accuracy
// reference. cap > 0 overrides the iteration cap.
std::unique_ptr<PatchSimulation> MakePatch(int config, int cap = 0) {
  const textile::FabricMaterial material = textile::MaterialFromKes(scene::LoadKesFabric("wang2011_black_denim_11oz"));
  textile::FabricModel model = textile::BuildFabricModel(material, {0.02, 0.02, 20, 20});
  textile::Placement placement;
  placement.origin_W = V(-0.01, -0.01, 0.0);
  textile::FabricState state = textile::MakeRestState(model, placement);
  for (int p : model.mesh.BorderParticles()) state.Fix(p);
  textile::StepOptions step;
  step.dt_s = 0.001;
  step.cg_tolerance = 1e-3;
  step.cg_max_iterations = 100;
  step.preconditioner = textile::Preconditioner::kBlockJacobi;
  if (config == 1) {
    step.cg_tolerance = 1e-2;
    step.cg_max_iterations = 20;
  } else if (config == 2) {
    step.cg_tolerance = 1e-2;
    step.preconditioner = textile::Preconditioner::kMultilevel;
  } else if (config == 3) {
    step = HapticPatchStepOptions(0.001);
  } else if (config == 4) {
    step = HapticPatchStepOptions(0.0002);
  } else if (config == 9) {
    step.cg_tolerance = 1e-9;
    step.cg_max_iterations = 5000;
  }
  if (cap > 0) step.cg_max_iterations = cap;
  return std::make_unique<PatchSimulation>(std::move(model), std::move(state), step, ContactOptions{});
}

void Report(benchmark::State& state, std::vector<double>* us) {
  if (us->empty()) return;
  std::sort(us->begin(), us->end());
  state.counters["p50_us"] = (*us)[us->size() / 2];
  state.counters["p99_us"] = (*us)[static_cast<std::size_t>(0.99 * static_cast<double>(us->size() - 1))];
}

// Two-finger pinch (VIII/IX) sliding slowly.
void BM_PinchTick(benchmark::State& state) {
  auto sim = MakePatch(static_cast<int>(state.range(0)));
  const double r = ContactOptions{}.thumb.radius_m + ContactOptions{}.fabric_half_thickness_m;
  for (int k = 0; k < 200; ++k) {
    const double d = std::min(1.0, k / 100.0) * 0.002;
    sim->Tick({true, Facing(V(0, 0, r - d), V(0, 0, -1))}, {true, Facing(V(0, 0, -(r - d)), V(0, 0, 1))});
  }
  std::vector<double> us;
  us.reserve(1 << 20);
  int k = 0;
  double iterations = 0.0;
  for (auto _ : state) {
    const double y = 0.002 * std::sin(1e-3 * k++);
    const auto t0 = std::chrono::steady_clock::now();
    const ContactOutput& out =
        sim->Tick({true, Facing(V(0, y, r - 0.002), V(0, 0, -1))}, {true, Facing(V(0, y, -(r - 0.002)), V(0, 0, 1))});
    const auto t1 = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(out.finger[0].force_W_N);
    if (us.size() < us.capacity()) us.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
    iterations += sim->last_step().cg.iterations;
  }
  state.counters["samples"] = sim->solver().output().pinch.samples;
  state.counters["cg_iterations"] = benchmark::Counter(iterations, benchmark::Counter::kAvgIterations);
  Report(state, &us);
}
BENCHMARK(BM_PinchTick)->Arg(0)->Arg(1)->Arg(2)->Arg(3)->Arg(4)->Unit(benchmark::kMicrosecond);

// One finger pressing and rubbing (IV/V, the V-proxy).
void BM_OneFingerTick(benchmark::State& state) {
  auto sim = MakePatch(static_cast<int>(state.range(0)));
  const double r = ContactOptions{}.thumb.radius_m + ContactOptions{}.fabric_half_thickness_m;
  for (int k = 0; k < 200; ++k) {
    sim->Tick({true, Facing(V(0, 0, r - std::min(1.0, k / 100.0) * 0.002), V(0, 0, -1))}, {});
  }
  std::vector<double> us;
  us.reserve(1 << 20);
  int k = 0;
  double iterations = 0.0;
  for (auto _ : state) {
    const double y = 0.003 * std::sin(1e-3 * k++);
    const auto t0 = std::chrono::steady_clock::now();
    const ContactOutput& out = sim->Tick({true, Facing(V(0, y, r - 0.002), V(0, 0, -1))}, {});
    const auto t1 = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(out.finger[0].force_W_N);
    if (us.size() < us.capacity()) us.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
    iterations += sim->last_step().cg.iterations;
  }
  state.counters["particles"] = sim->solver().output().finger[0].contact_particles;
  state.counters["cg_iterations"] = benchmark::Counter(iterations, benchmark::Counter::kAvgIterations);
  Report(state, &us);
}
BENCHMARK(BM_OneFingerTick)->Arg(0)->Arg(1)->Arg(2)->Arg(3)->Arg(4)->Unit(benchmark::kMicrosecond);

// The contact code alone (ContactSolver::Prepare + Resolve, no fabric step) on the fabric as the
// ticks above leave it: what the contact part of a tick costs, apart from the fabric step.
void ContactOnly(benchmark::State& state, bool pinch) {
  auto sim = MakePatch(1);
  const double r = ContactOptions{}.thumb.radius_m + ContactOptions{}.fabric_half_thickness_m;
  auto thumb = [&](double y, double d) { return FingerInput{true, Facing(V(0, y, r - d), V(0, 0, -1))}; };
  auto index = [&](double y, double d) {
    return pinch ? FingerInput{true, Facing(V(0, y, -(r - d)), V(0, 0, 1))} : FingerInput{};
  };
  for (int k = 0; k < 200; ++k) {
    const double d = std::min(1.0, k / 100.0) * 0.002;
    sim->Tick(thumb(0.0, d), index(0.0, d));
  }
  ContactSolver& solver = sim->solver();
  textile::FabricState& fabric = sim->state();
  std::vector<double> us;
  us.reserve(1 << 20);
  int k = 0;
  for (auto _ : state) {
    const double y = 0.002 * std::sin(1e-3 * k++);
    const auto t0 = std::chrono::steady_clock::now();
    solver.Prepare(thumb(y, 0.002), index(y, 0.002), sim->dt_s(), &fabric);
    const ContactOutput& out = solver.Resolve(fabric);
    const auto t1 = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(out.finger[0].force_W_N);
    if (us.size() < us.capacity()) us.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
  }
  state.counters["samples"] = solver.output().pinch.samples;
  state.counters["particles"] = solver.output().finger[0].contact_particles;
  Report(state, &us);
}
void BM_PinchContactOnly(benchmark::State& state) { ContactOnly(state, true); }
void BM_OneFingerContactOnly(benchmark::State& state) { ContactOnly(state, false); }
BENCHMARK(BM_PinchContactOnly)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_OneFingerContactOnly)->Unit(benchmark::kMicrosecond);

// Accuracy of a solver configuration: the finger forces over 2 s of a pinch (or one finger)
// rubbing 3 mm back and forth at 1 Hz, against the same run solved to 1e-9 (block Jacobi).
void Accuracy(benchmark::State& state, bool pinch) {
  const double r = ContactOptions{}.thumb.radius_m + ContactOptions{}.fabric_half_thickness_m;
  auto thumb = [&](double y, double d) { return FingerInput{true, Facing(V(0, y, r - d), V(0, 0, -1))}; };
  auto index = [&](double y, double d) {
    return pinch ? FingerInput{true, Facing(V(0, y, -(r - d)), V(0, 0, 1))} : FingerInput{};
  };
  double err_max = 0.0, err2 = 0.0, ref_max = 0.0, iterations = 0.0;
  int ticks = 0;
  for (auto _ : state) {
    auto sim = MakePatch(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
    auto ref = MakePatch(9);
    const double dt_s = sim->dt_s();
    const int ticks_per_0p1_s = static_cast<int>(std::lround(0.1 / dt_s));
    for (int k = 0; k < 21 * ticks_per_0p1_s; ++k) {
      const double t_s = k * dt_s;
      const double d = std::min(1.0, t_s / 0.1) * 0.002;
      const double y = t_s < 0.1 ? 0.0 : 0.003 * std::sin(2.0 * M_PI * (t_s - 0.1));
      const Eigen::Vector3d f = sim->Tick(thumb(y, d), index(y, d)).finger[0].force_W_N;
      iterations += sim->last_step().cg.iterations;
      const Eigen::Vector3d f_ref = ref->Tick(thumb(y, d), index(y, d)).finger[0].force_W_N;
      err_max = std::max(err_max, (f - f_ref).norm());
      err2 += (f - f_ref).squaredNorm();
      ref_max = std::max(ref_max, f_ref.norm());
      ++ticks;
    }
  }
  state.counters["force_err_max_N"] = err_max;
  state.counters["force_err_rms_N"] = std::sqrt(err2 / ticks);
  state.counters["force_ref_max_N"] = ref_max;
  state.counters["cg_iterations"] = iterations / ticks;  // mean per tick: the solver's cost
}
void BM_PinchAccuracy(benchmark::State& state) { Accuracy(state, true); }
void BM_OneFingerAccuracy(benchmark::State& state) { Accuracy(state, false); }
// Args: solver config, iteration cap (0: the config's own).
void AccuracyArgs(benchmark::internal::Benchmark* b) {
  for (const auto& [config, cap] :
       std::vector<std::pair<int, int>>{{0, 0}, {1, 0}, {3, 0}, {3, 3}, {3, 4}, {3, 5}, {3, 20}}) {
    b->Args({config, cap});
  }
  b->Iterations(1)->Unit(benchmark::kMillisecond);
}
BENCHMARK(BM_PinchAccuracy)->Apply(AccuracyArgs);
BENCHMARK(BM_OneFingerAccuracy)->Apply(AccuracyArgs);

// The fabric step alone (no fingers): the floor under both.
void BM_PatchStepOnly(benchmark::State& state) {
  auto sim = MakePatch(static_cast<int>(state.range(0)));
  for (int k = 0; k < 50; ++k) sim->Tick({}, {});
  double iterations = 0.0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(sim->Tick({}, {}));
    iterations += sim->last_step().cg.iterations;
  }
  state.counters["cg_iterations"] = benchmark::Counter(iterations, benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_PatchStepOnly)->Arg(0)->Arg(1)->Arg(2)->Arg(3)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace haptex::contact

BENCHMARK_MAIN();
