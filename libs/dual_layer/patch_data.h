#pragma once
// A local patch as the global layer cuts it and the local layer receives it: the grid rectangle's
// particles in grid order (u fastest), their state, and which of them the global layer holds.
// Plain arrays with their capacity reserved once, so filling a patch of up to `max_particles`
// does not allocate.

#include <cstdint>
#include <vector>

namespace haptex::dual_layer {

struct PatchData {
  PatchData() = default;
  /// Reserves every array for patches of up to `max_particles`.
  explicit PatchData(int max_particles);

  std::uint64_t patch_id = 0;     ///< increases with every patch cut
  std::uint64_t global_step = 0;  ///< the global step the patch was cut at
  double global_time_s = 0.0;     ///< simulated time of that step
  double global_dt_s = 0.0;       ///< the global step; the local layer reports once per step
  /// The global link's round trip in global steps as global_sim measured it (global_link_delay.h):
  /// how far the local layer may extrapolate the border.
  std::uint32_t link_round_trip_steps = 0;
  int num_particles = 0;
  std::vector<std::uint32_t> ids;        ///< fabric ids (refined particles above the fabric's count)
  std::vector<double> rest_uv_m;         ///< 2 per particle (u warp, v weft)
  std::vector<double> x_W_m;             ///< 3 per particle
  std::vector<double> v_W_m_per_s;       ///< 3 per particle
  std::vector<double> mass_kg;           ///< 1 per particle (the local layer rebuilds masses from the material)
  std::vector<std::uint8_t> border;      ///< 1: held where the global layer puts it
  std::vector<std::uint32_t> triangles;  ///< 3 patch indices per triangle (the local layer rebuilds them)

  /// Empties every array, keeping its capacity.
  void Clear();
};

/// Whether a received patch can be built: at least 4 particles, arrays of matching sizes, a
/// positive finite global step, every id below `max_particle_id`, every coordinate finite.
/// Masses and triangles are not checked (the local layer rebuilds them).
bool IsBuildable(const PatchData& patch, std::uint32_t max_particle_id);

}  // namespace haptex::dual_layer
