#include "services/global_sim/global_sim_codec.h"

#include <algorithm>

#include "libs/codec/cloth_positions.h"
#include "libs/codec/message_conversion.h"

namespace haptex::global_sim {

std::array<dual_layer::FingerSphere, 2> FingerSpheres(const v1::FingerStates& states, double finger_reach_m,
                                                      double global_dt_s, double margin_m) {
  std::array<dual_layer::FingerSphere, 2> spheres{};
  if (!states.device_ok()) return spheres;
  for (const v1::FingerState& f : states.fingers()) {
    const int slot = codec::FingerSlot(f.finger());
    if (slot < 0) continue;
    spheres[static_cast<std::size_t>(slot)] =
        dual_layer::SweptSphere(codec::ToEigen(f.position_w_m()), codec::ToEigen(f.predicted_position_w_m()),
                                codec::ToEigen(f.velocity_w_m_per_s()), finger_reach_m, global_dt_s, margin_m);
  }
  return spheres;
}

void ToMessage(const dual_layer::PatchData& patch, v1::LocalPatch* out) {
  out->set_patch_id(patch.patch_id);
  out->set_global_step(patch.global_step);
  out->set_global_time_s(patch.global_time_s);
  out->set_global_dt_s(patch.global_dt_s);
  out->set_link_round_trip_steps(patch.link_round_trip_steps);
  out->mutable_particle_ids()->Assign(patch.ids.begin(), patch.ids.end());
  out->mutable_rest_uv_m()->Assign(patch.rest_uv_m.begin(), patch.rest_uv_m.end());
  out->mutable_position_w_m()->Assign(patch.x_W_m.begin(), patch.x_W_m.end());
  out->mutable_velocity_w_m_per_s()->Assign(patch.v_W_m_per_s.begin(), patch.v_W_m_per_s.end());
  out->mutable_mass_kg()->Assign(patch.mass_kg.begin(), patch.mass_kg.end());
  out->clear_is_border();
  for (std::uint8_t b : patch.border) out->add_is_border(b != 0);
  out->mutable_triangles()->Assign(patch.triangles.begin(), patch.triangles.end());
}

bool CopyResult(const v1::PatchResult& result, dual_layer::PatchResultData* out) {
  const auto m = static_cast<std::size_t>(result.particle_ids_size());
  if (static_cast<std::size_t>(result.position_w_m_size()) != 3 * m ||
      static_cast<std::size_t>(result.velocity_w_m_per_s_size()) != 3 * m ||
      static_cast<std::size_t>(result.external_force_w_n_size()) != 3 * m || m > out->ids.capacity()) {
    return false;
  }
  out->patch_id = result.patch_id();
  out->global_step = result.global_step();
  out->local_ticks = result.local_ticks();
  out->ids.assign(result.particle_ids().begin(), result.particle_ids().end());
  out->x_W_m.assign(result.position_w_m().begin(), result.position_w_m().end());
  out->v_W_m_per_s.assign(result.velocity_w_m_per_s().begin(), result.velocity_w_m_per_s().end());
  out->external_force_W_N.assign(result.external_force_w_n().begin(), result.external_force_w_n().end());
  return true;
}

void FillClothFrame(const textile::FabricModel& model, const textile::FabricState& state,
                    const dual_layer::PatchRect& patch, std::uint64_t frame_index, int chunk, v1::ClothFrame* out) {
  const int n = model.num_particles;
  out->set_frame_index(frame_index);
  out->set_sim_time_s(state.time_s);
  out->set_particles_u(static_cast<std::uint32_t>(model.mesh.particles_warp()));
  out->set_particles_v(static_cast<std::uint32_t>(model.mesh.particles_weft()));
  out->set_first_particle(static_cast<std::uint32_t>(chunk * kClothFrameChunkParticles));
  out->set_chunk_index(static_cast<std::uint32_t>(chunk));
  out->set_chunk_count(static_cast<std::uint32_t>(ClothFrameChunks(n)));
  const int first = chunk * kClothFrameChunkParticles;
  const int end = std::min(n, first + kClothFrameChunkParticles);
  codec::EncodeClothPositions(state.x_W_m.data() + 3 * first, end - first, codec::kClothQuantumM, out);
  const bool cut = !patch.empty();
  out->set_patch_u_begin(cut ? static_cast<std::uint32_t>(patch.i0) : 0);
  out->set_patch_u_end(cut ? static_cast<std::uint32_t>(patch.i1 + 1) : 0);
  out->set_patch_v_begin(cut ? static_cast<std::uint32_t>(patch.j0) : 0);
  out->set_patch_v_end(cut ? static_cast<std::uint32_t>(patch.j1 + 1) : 0);
}

}  // namespace haptex::global_sim
