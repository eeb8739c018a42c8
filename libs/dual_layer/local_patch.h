#pragma once
// One local patch as the local layer runs it: the patch simulation (fabric + contact), the map
// between its particles and the whole fabric's, and what it accumulates for the PatchResult.
// BuildLocalPatch allocates (build it off the haptic loop); Tick, HandOff and FillPatchResult do
// not.

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "libs/contact/patch_simulation.h"
#include "libs/dual_layer/patch_data.h"
#include "libs/dual_layer/patch_result.h"
#include "libs/textile/kes_material.h"

namespace haptex::dual_layer {

struct LocalPatch {
  std::unique_ptr<contact::PatchSimulation> sim;
  std::uint64_t patch_id = 0;
  std::uint64_t global_step = 0;  ///< the global step the patch was cut at
  double global_dt_s = 0.0;
  std::vector<std::uint32_t> global_id;          ///< per patch particle
  std::vector<int> local_of_global;              ///< per particle id (fabric and refined): patch index or -1
  std::vector<std::array<int, 6>> triangles_of;  ///< per patch particle: triangles it is the first vertex of (-1: none)
  Eigen::VectorXd force_sum_W_N;                 ///< contact force summed over the ticks since the last result
  int ticks_since_result = 0;

  /// One haptic tick of the patch with the fingers' poses at its end; accumulates the contact
  /// forces for the next result.
  const contact::ContactOutput& Tick(const contact::FingerInput& thumb, const contact::FingerInput& index);
  /// True once a global step's worth of ticks of `local_dt_s` has passed since the last result
  /// (within half a tick).
  bool ResultDue(double local_dt_s) const { return ticks_since_result * local_dt_s >= global_dt_s - 0.5 * local_dt_s; }
};

/// Builds a patch from received data: checks it is a grid rectangle (ids, rest coordinates),
/// makes the fabric model of that rectangle, sets positions and velocities, holds the border
/// particles and moves them with their velocities, extrapolated only as far as the global link's
/// round trip allows (BorderVelocityWeight). @throws std::invalid_argument naming what is inconsistent.
std::unique_ptr<LocalPatch> BuildLocalPatch(const PatchData& data, const textile::FabricMaterial& material,
                                            const textile::ModelOptions& model_options,
                                            const textile::StepOptions& step,
                                            const contact::ContactOptions& contact_options, int particle_id_space);

/// Carries the local state of `old` into `fresh` by particle id, so the hand-off applies no force
/// step: positions and velocities of shared free particles (the local ones are newer), and each
/// finger's per-particle contact (held point, sliding), the pinch samples on triangles both
/// patches share, the classifier's hysteresis and stiffness estimates, and the PatchResult
/// accumulation (ticks since the last result, contact force sums of the shared free particles).
/// Returns the number of particles carried.
int HandOff(const LocalPatch& old, LocalPatch* fresh);

/// Fills `out` (reusing its storage) with the patch's free particles and the mean contact force
/// since the last result, then restarts the accumulation.
void FillPatchResult(std::uint64_t global_step, LocalPatch* patch, PatchResultData* out);

}  // namespace haptex::dual_layer
