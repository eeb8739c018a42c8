#include "services/local_contact/patch_builder.h"

#include <stdexcept>

#include "services/local_contact/local_contact_codec.h"

namespace haptex::local_contact {

PatchBuilder::PatchBuilder(PatchBuildSpec spec, Threading threading) : spec_(std::move(spec)) {
  for (int i = 0; i < kSlots; ++i) {
    slots_[static_cast<std::size_t>(i)] = dual_layer::PatchData(spec_.max_patch_particles);
    free_slots_.TryPush(i);
  }
  if (threading == Threading::kCallerRuns) return;
  thread_ = std::thread([this] {
    while (!stop_.load(std::memory_order_acquire)) {
      const std::uint32_t seen = work_.load(std::memory_order_acquire);
      if (RunOnce()) continue;
      // nothing to do until the loop hands something over (or takes a built patch)
      work_.wait(seen, std::memory_order_acquire);
    }
  });
}

PatchBuilder::~PatchBuilder() {
  stop_.store(true, std::memory_order_release);
  Wake();
  if (thread_.joinable()) thread_.join();
}

void PatchBuilder::Wake() {
  work_.fetch_add(1, std::memory_order_release);
  work_.notify_one();
}

PatchBuilder::Submitted PatchBuilder::Submit(const v1::LocalPatch& patch) {
  int slot = -1;
  if (!free_slots_.TryPop(&slot)) return Submitted::kBusy;
  if (CopyPatch(patch, static_cast<std::uint32_t>(spec_.particle_id_space), &slots_[static_cast<std::size_t>(slot)]) !=
      PatchCopy::kOk) {
    free_slots_.TryPush(slot);
    return Submitted::kRejected;
  }
  pending_slots_.TryPush(slot);  // cannot be full: it holds fewer than kSlots
  Wake();
  return Submitted::kQueued;
}

std::unique_ptr<dual_layer::LocalPatch> PatchBuilder::TakeBuilt() {
  std::unique_ptr<dual_layer::LocalPatch> patch;
  if (built_.TryPop(&patch)) Wake();  // room to hand back the next one
  return patch;
}

void PatchBuilder::Dispose(std::unique_ptr<dual_layer::LocalPatch> patch) {
  // Full only if the builder stalled for more hand-offs than the ring holds; then the loop frees
  // the patch itself rather than leak it.
  if (disposal_.TryPush(std::move(patch))) Wake();
}

bool PatchBuilder::RunOnce() {
  bool worked = false;
  std::unique_ptr<dual_layer::LocalPatch> old;
  while (disposal_.TryPop(&old)) {
    old.reset();
    worked = true;
  }
  if (built_.size() == 4) return worked;  // the loop has not taken the last ones yet
  int slot = -1;
  if (!pending_slots_.TryPop(&slot)) return worked;
  try {
    std::unique_ptr<dual_layer::LocalPatch> patch =
        dual_layer::BuildLocalPatch(slots_[static_cast<std::size_t>(slot)], spec_.material, spec_.model_options,
                                    spec_.step, spec_.contact, spec_.particle_id_space);
    built_.TryPush(std::move(patch));  // room checked above; only this thread pushes
  } catch (const std::exception&) {
    build_failures_.fetch_add(1, std::memory_order_relaxed);
  }
  free_slots_.TryPush(slot);
  return true;
}

}  // namespace haptex::local_contact
