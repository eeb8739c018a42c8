// Cost of one 5 kHz tick on each side of the GRAB link (budget: 200 us per tick, shared with the
// socket work of the services).
//   device_bench --benchmark_min_time=0.5

#include <benchmark/benchmark.h>

#include <array>
#include <memory>
#include <vector>

#include "libs/device/crc32c.h"
#include "libs/device/device_bridge.h"
#include "libs/device/mock_grab_controller.h"

namespace haptex::device {
namespace {

constexpr double kTick_s = 2e-4;
constexpr std::size_t kFrames = 1 << 14;
using StatusBytes = std::array<std::byte, kStatusFrameSize>;
using CommandBytes = std::array<std::byte, kCommandFrameSize>;

// Realistic controller traffic: a mock rubbing the fabric, both fingers moving.
std::vector<StatusBytes> RecordStatusFrames() {
  ScriptParams script;
  script.kind = ScriptKind::kRub;
  MockGrabController mock(MockControllerConfig{}, script);
  std::vector<StatusBytes> frames(kFrames);
  for (std::size_t k = 0; k < kFrames; ++k) mock.Step(1.3 + k * kTick_s, kTick_s, frames[k]);
  return frames;
}

ForceModel Wall() {
  ForceModel m;
  const Eigen::Vector3d n(0.0, 1.0, 0.0);
  m.force0_W_N = 2.0 * n;
  m.stiffness_W_N_per_m = -1250.0 * n * n.transpose();
  m.ttl_s = 0.010;
  return m;
}

// decode + state estimation + ForceModel evaluation + safety + encode, both fingers
void BM_BridgeTick(benchmark::State& state) {
  const std::vector<StatusBytes> frames = RecordStatusFrames();
  auto bridge = std::make_unique<DeviceBridge>(DeviceBridgeConfig{});
  CommandBytes out{};
  std::size_t k = 0;
  double t = 0.0;
  for (auto _ : state) {
    if (k == kFrames) {  // sequences restart: a fresh bridge (not timed)
      state.PauseTiming();
      bridge = std::make_unique<DeviceBridge>(DeviceBridgeConfig{});
      k = 0;
      state.ResumeTiming();
    }
    t += kTick_s;
    bridge->OnStatusDatagram(frames[k++], t);
    if (k % 5 == 0) {
      const std::uint64_t basis = bridge->finger_state(Manipulator::kThumb).controller_sequence;
      bridge->SetForceModel(Manipulator::kThumb, Wall(), t, basis);
      bridge->SetForceModel(Manipulator::kIndex, Wall(), t, basis);
    }
    bridge->Tick(t, kTick_s, out);
    benchmark::DoNotOptimize(out);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_BridgeTick);

// command decode + two finger dynamics + sensor model + status encode
void BM_MockTick(benchmark::State& state) {
  ScriptParams script;
  script.kind = ScriptKind::kRub;
  MockGrabController mock(MockControllerConfig{}, script);
  std::vector<CommandBytes> commands(kFrames);
  for (std::size_t k = 0; k < kFrames; ++k) {
    CommandFrame c;
    c.sequence = static_cast<std::uint32_t>(k + 1);
    c.manipulators[0].force_D_N = {0.1f, 1.0f, 0.0f};
    c.manipulators[0].flags = command_flags::kForceEnable;
    c.manipulators[1].force_D_N = {0.1f, -1.0f, 0.0f};
    c.manipulators[1].flags = command_flags::kForceEnable;
    EncodeCommandFrame(c, commands[k]);
  }
  StatusBytes out{};
  std::size_t k = 0;
  double t = 0.0;
  for (auto _ : state) {
    // the 5 ms host timeout resynchronises sequences after a wrap of the table
    mock.OnCommandDatagram(commands[k++ % kFrames], t);
    mock.Step(t, kTick_s, out);
    t += kTick_s;
    benchmark::DoNotOptimize(out);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_MockTick);

void BM_DecodeStatusFrame(benchmark::State& state) {
  const std::vector<StatusBytes> frames = RecordStatusFrames();
  StatusFrame f;
  std::size_t k = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(DecodeStatusFrame(frames[k++ % kFrames], GrabValueLimits{}, &f));
    benchmark::DoNotOptimize(f);
  }
}
BENCHMARK(BM_DecodeStatusFrame);

void BM_EncodeCommandFrame(benchmark::State& state) {
  CommandFrame c;
  CommandBytes out{};
  for (auto _ : state) {
    ++c.sequence;
    EncodeCommandFrame(c, out);
    benchmark::DoNotOptimize(out);
  }
}
BENCHMARK(BM_EncodeCommandFrame);

void BM_Crc32cStatusBody(benchmark::State& state) {
  const std::vector<StatusBytes> frames = RecordStatusFrames();
  std::size_t k = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(Crc32c(std::span<const std::byte>(frames[k++ % kFrames]).first(112)));
  }
}
BENCHMARK(BM_Crc32cStatusBody);

void BM_ForceSafetyStep(benchmark::State& state) {
  ForceSafety safety(ForceSafetyConfig{});
  SafetyInput in;
  in.requested_W_N = {30.0, -10.0, 5.0};
  in.model_ttl_s = 0.01;
  in.output_allowed = true;
  for (auto _ : state) {
    in.requested_W_N.x() = -in.requested_W_N.x();
    benchmark::DoNotOptimize(safety.Step(in, kTick_s));
  }
}
BENCHMARK(BM_ForceSafetyStep);

}  // namespace
}  // namespace haptex::device

BENCHMARK_MAIN();
