// Speed of the tactile renderer. The real-time figure is BM_TwoFingerFrame: one display frame
// (2 ms at 500 Hz) for two sliding fingers; the budget is 100 us on one core.

#include <benchmark/benchmark.h>

#include "libs/tactile/periodicity.h"
#include "libs/tactile/pin_renderer.h"
#include "libs/tactile/weave_surface.h"

namespace haptex::tactile {
namespace {

WeaveParams BenchWeave() {
  WeaveParams p;
  p.pattern = WeavePattern::kTwill;
  p.hairiness_fraction = 0.3;
  p.smd_um = 6.0;
  return p;
}

const RendererModel& Model() {
  static const RendererModel model = [] {
    PeriodicityOptions options;
    options.noise_size = 64;
    return RendererModel(AnalysePeriodicity(GenerateWeave(BenchWeave()), options));
  }();
  return model;
}

struct Finger {
  FingerInput input;
  FingerRenderState state;
};

// Each iteration advances two sliding fingers by `steps` inputs spanning one display frame.
void RunFrames(benchmark::State& bench, int steps_per_frame) {
  const RendererModel& model = Model();
  const double frame_s = 1.0 / model.config().display_rate_hz;
  const double dt = frame_s / steps_per_frame;
  Finger fingers[2];
  fingers[0].input.touch_point_m = Eigen::Vector2d(0.05, 0.05);
  fingers[0].input.slip_velocity_m_per_s = Eigen::Vector2d(0.08, 0.03);
  fingers[0].input.orientation_rad = 0.4;
  fingers[1].input.touch_point_m = Eigen::Vector2d(0.07, 0.04);
  fingers[1].input.slip_velocity_m_per_s = Eigen::Vector2d(-0.05, 0.06);
  fingers[1].input.orientation_rad = -2.0;
  for (Finger& f : fingers) {
    f.input.in_contact = true;
    f.input.normal_force_N = 1.5;
  }
  RenderWorkspace workspace;
  std::int64_t frames = 0;
  for (auto _ : bench) {
    for (Finger& f : fingers) {
      for (int s = 0; s < steps_per_frame; ++s) {
        f.input.touch_point_m += f.input.slip_velocity_m_per_s * dt;
        frames += RenderStep(model, f.input, dt, &f.state, &workspace);
      }
      benchmark::DoNotOptimize(f.state.frame);
    }
  }
  bench.counters["frames_per_iteration"] = static_cast<double>(frames) / static_cast<double>(bench.iterations());
}

void BM_TwoFingerFrame(benchmark::State& bench) { RunFrames(bench, 1); }
BENCHMARK(BM_TwoFingerFrame)->Unit(benchmark::kMicrosecond);

// The same frame fed by 1 kHz contact updates (two steps per finger per frame).
void BM_TwoFingerFrameAt1kHzInput(benchmark::State& bench) { RunFrames(bench, 2); }
BENCHMARK(BM_TwoFingerFrameAt1kHzInput)->Unit(benchmark::kMicrosecond);

// Pre-processing, not real-time: weave generation + periodicity analysis of a 256 x 256 map.
void BM_AnalysePeriodicity256(benchmark::State& bench) {
  const HeightMap map = GenerateWeave(BenchWeave());
  PeriodicityOptions options;
  options.noise_size = 64;
  for (auto _ : bench) benchmark::DoNotOptimize(AnalysePeriodicity(map, options));
}
BENCHMARK(BM_AnalysePeriodicity256)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace haptex::tactile

BENCHMARK_MAIN();
