#pragma once
// What the local layer returns once per global step: the patch's free particles (where the local
// layer put them) and the mean contact force on each over the step.

#include <cstdint>
#include <vector>

namespace haptex::dual_layer {

struct PatchResultData {
  PatchResultData() = default;
  /// Reserves every array for results of up to `max_particles`.
  explicit PatchResultData(int max_particles);

  std::uint64_t patch_id = 0;
  std::uint64_t global_step = 0;  ///< the step this result is for
  std::uint32_t local_ticks = 0;  ///< local ticks the forces are averaged over
  std::vector<std::uint32_t> ids;
  std::vector<double> x_W_m;               ///< 3 per particle
  std::vector<double> v_W_m_per_s;         ///< 3 per particle
  std::vector<double> external_force_W_N;  ///< 3 per particle: mean contact force over the step

  int num_particles() const { return static_cast<int>(ids.size()); }
  /// Empties every array, keeping its capacity.
  void Clear();
};

}  // namespace haptex::dual_layer
