#pragma once
// A LocalPatch copied out of the receive arena into storage sized once, so the haptic loop can
// take a patch without allocating and hand it to the builder thread.

#include <cstdint>
#include <vector>

#include "haptex/v1/local_patch.pb.h"

namespace haptex::local_contact {

struct PatchData {
  explicit PatchData(int max_particles);

  std::uint64_t patch_id = 0;
  double global_dt_s = 0.0;
  int num_particles = 0;
  std::vector<std::uint32_t> ids;
  std::vector<double> rest_uv_m, x_W_m, v_W_m_per_s;
  std::vector<std::uint8_t> border;

  enum class Copy { kOk, kTooLarge, kMalformed };
  /// Copies `patch` (arrays of consistent sizes, finite values, ids below `max_particle_id`).
  Copy CopyFrom(const v1::LocalPatch& patch, std::uint32_t max_particle_id);
};

}  // namespace haptex::local_contact
