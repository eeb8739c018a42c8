#pragma once
// Builds local patches off the haptic loop. The loop hands a received LocalPatch over (copied into
// one of a few preallocated slots: no allocation, never waits); a builder thread builds it
// (dual_layer::BuildLocalPatch allocates) and hands the finished patch back, owned through
// std::unique_ptr; the loop hands replaced patches back to be freed on the builder thread, so the
// haptic loop neither allocates nor frees.

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <thread>

#include "haptex/v1/local_patch.pb.h"
#include "libs/contact/contact_options.h"
#include "libs/dual_layer/local_patch.h"
#include "libs/dual_layer/patch_data.h"
#include "libs/runtime/spsc_ring.h"
#include "libs/textile/kes_material.h"
#include "libs/textile/step_options.h"

namespace haptex::local_contact {

/// What every patch is built with.
struct PatchBuildSpec {
  textile::FabricMaterial material;
  textile::ModelOptions model_options;
  textile::StepOptions step;
  contact::ContactOptions contact;
  int particle_id_space = 0;       ///< the fabric's ids plus the refined ones (dual_layer::RefinedGrid)
  int max_patch_particles = 4096;  ///< larger patches are refused
};

class PatchBuilder final {
 public:
  enum class Threading { kOwnThread, kCallerRuns };
  /// kOwnThread starts the builder thread; kCallerRuns leaves the building to RunOnce (tests).
  PatchBuilder(PatchBuildSpec spec, Threading threading);
  /// Stops the thread and frees every patch it still holds.
  ~PatchBuilder();
  PatchBuilder(const PatchBuilder&) = delete;
  PatchBuilder& operator=(const PatchBuilder&) = delete;

  enum class Submitted { kQueued, kBusy, kRejected };
  /// Loop side: queues `patch` for building. kBusy when every slot is taken (the patch is
  /// dropped; the next one follows within a global step), kRejected when it cannot be built.
  Submitted Submit(const v1::LocalPatch& patch);
  /// Loop side: the oldest finished patch, or null.
  std::unique_ptr<dual_layer::LocalPatch> TakeBuilt();
  /// Loop side: a patch the loop is done with, freed on the builder thread.
  void Dispose(std::unique_ptr<dual_layer::LocalPatch> patch);

  /// Builder side: frees disposed patches, then builds one queued patch if there is room to hand
  /// it back. Returns true when it did anything. The builder thread calls it; with kCallerRuns the
  /// test does.
  bool RunOnce();

  /// Queued patches that failed to build (BuildLocalPatch refused them).
  std::uint64_t build_failures() const { return build_failures_.load(std::memory_order_relaxed); }

 private:
  static constexpr int kSlots = 3;
  void Wake();

  PatchBuildSpec spec_;
  std::array<dual_layer::PatchData, kSlots> slots_;
  runtime::SpscRing<int, 4> free_slots_, pending_slots_;
  runtime::SpscRing<std::unique_ptr<dual_layer::LocalPatch>, 4> built_;
  // at most one disposal per patch taken, and the builder empties this ring before each build
  runtime::SpscRing<std::unique_ptr<dual_layer::LocalPatch>, 8> disposal_;
  std::atomic<std::uint64_t> build_failures_{0};
  std::atomic<std::uint32_t> work_{0};  // bumped (and notified) whenever the loop hands something over
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace haptex::local_contact
