// The kernels of an implicit fabric step, alone: force + Jacobian assembly (AccumulateForces),
// the CG product (MultiplySplitRows) and Gauss-Seidel's set-up and split product, for 20x20,
// 41x41 and 81x81 denim in a deformed, moving state. Quieter than the whole step on a busy
// machine.
//
//   textile_kernels_benchmark --benchmark_repetitions=3 --benchmark_report_aggregates_only=true

#include <vector>

#include <benchmark/benchmark.h>

#include "libs/scene/fabric_conversion.h"
#include "libs/textile/fabric_forces.h"
#include "libs/textile/gauss_seidel_preconditioner.h"
#include "libs/textile/kes_material.h"
#include "libs/textile/validation.h"

namespace haptex::textile {
namespace {

struct Setup {
  FabricModel model;
  FabricState state;
  Eigen::VectorXd f, dfdx_v;
  std::vector<Eigen::Matrix3d> system;
  std::vector<double> scalars;
  ForceSink sink;

  explicit Setup(int n)
      : model(BuildFabricModel(MaterialFromKes(scene::LoadKesFabric("wang2011_black_denim_11oz")), {0.2, 0.2, n, n})),
        state(MakeRestState(model)) {
    for (int p = 0; p < model.num_particles; ++p) {
      state.x(p) = state.x(p).cwiseProduct(Eigen::Vector3d(1.01, 0.995, 1.0));
    }
    validation::Perturb(&state, 2e-4, 0.05, 7);
    for (int p = 0; p < n; ++p) state.Fix(p);  // one edge constrained, as on the stand
    f = Eigen::VectorXd::Zero(3 * model.num_particles);
    dfdx_v = f;
    system.assign(static_cast<std::size_t>(model.pattern.num_blocks()), Eigen::Matrix3d::Zero());
    sink.force_N = &f;
    sink.system = &system;
    sink.dx_scale = -1e-4;
    sink.dv_scale = -1e-2;
    sink.dfdx_v = &dfdx_v;
    sink.v = &state.v_W_m_per_s;
    for (int p = 0; p < model.num_particles; ++p) {
      system[static_cast<std::size_t>(model.pattern.diag_slot[static_cast<std::size_t>(p)])] +=
          model.mass_kg[p] * Eigen::Matrix3d::Identity();
    }
    AddConstantJacobians(model, &sink);
    for (int slot : model.product_rows.scalar_slot) {
      scalars.push_back(system[static_cast<std::size_t>(slot)](0, 0));
    }
    sink.constant_jacobians_added = true;
    AccumulateForces(model, state, &sink);
  }
};

void BM_Assembly(benchmark::State& bm) {
  Setup s(static_cast<int>(bm.range(0)));
  for (auto _ : bm) {
    s.f.setZero();
    s.dfdx_v.setZero();
    AccumulateForces(s.model, s.state, &s.sink);
    benchmark::DoNotOptimize(s.system.data());
  }
  bm.counters["triangles"] = static_cast<double>(s.model.triangles.size());
}
BENCHMARK(BM_Assembly)->Arg(20)->Arg(41)->Arg(81)->Unit(benchmark::kMicrosecond);

// Forces and (df/dx) v only, no system blocks: what a step that reuses its Jacobian assembles.
void BM_ForcesOnly(benchmark::State& bm) {
  Setup s(static_cast<int>(bm.range(0)));
  ForceSink forces_only = s.sink;
  forces_only.system = nullptr;
  for (auto _ : bm) {
    s.f.setZero();
    AccumulateForces(s.model, s.state, &forces_only);
    benchmark::DoNotOptimize(s.f.data());
  }
}
BENCHMARK(BM_ForcesOnly)->Arg(20)->Arg(41)->Arg(81)->Unit(benchmark::kMicrosecond);

void BM_Product(benchmark::State& bm) {
  Setup s(static_cast<int>(bm.range(0)));
  const ParticleMode* mode = s.state.mode.data();
  Eigen::VectorXd x = s.state.v_W_m_per_s, y = x;
  double xy = 0.0;
  for (auto _ : bm) {
    xy += MultiplySplitRows(
        s.model.product_rows, s.system, s.scalars, [mode](int r) { return mode[r] == ParticleMode::kFree; }, x, &y);
    benchmark::DoNotOptimize(y.data());
  }
  benchmark::DoNotOptimize(xy);
  bm.counters["blocks"] = s.model.pattern.num_blocks();
}
BENCHMARK(BM_Product)->Arg(20)->Arg(41)->Arg(81)->Unit(benchmark::kMicrosecond);

// Gauss-Seidel (SSOR) preconditioning: its per-step set-up (Update: the scaled diagonal blocks
// and their inverses) and one CG iteration's product with the split system (MultiplySplit: a
// backward and a forward sweep).
void BM_GaussSeidelUpdate(benchmark::State& bm) {
  Setup s(static_cast<int>(bm.range(0)));
  const ParticleMode* mode = s.state.mode.data();
  GaussSeidelPreconditioner gs(s.model.product_rows);
  for (auto _ : bm) {
    benchmark::DoNotOptimize(gs.Update(s.system, 1.4, [mode](int r) { return mode[r] == ParticleMode::kFree; }));
  }
}
BENCHMARK(BM_GaussSeidelUpdate)->Arg(20)->Arg(41)->Unit(benchmark::kMicrosecond);

void BM_GaussSeidelSplitProduct(benchmark::State& bm) {
  Setup s(static_cast<int>(bm.range(0)));
  const ParticleMode* mode = s.state.mode.data();
  GaussSeidelPreconditioner gs(s.model.product_rows);
  gs.Update(s.system, 1.4, [mode](int r) { return mode[r] == ParticleMode::kFree; });
  const int n = s.model.num_particles;
  PaddedVector x(n), t(n), z(n), y(n);
  for (int p = 0; p < n; ++p) {
    if (mode[p] == ParticleMode::kFree) x.row(p) = s.state.v(p);
  }
  double xy = 0.0;
  for (auto _ : bm) {
    xy += gs.MultiplySplit(s.system, s.scalars, x, &t, &z, &y);
    benchmark::DoNotOptimize(y.data());
  }
  benchmark::DoNotOptimize(xy);
}
BENCHMARK(BM_GaussSeidelSplitProduct)->Arg(20)->Arg(41)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace haptex::textile

BENCHMARK_MAIN();
