#pragma once
// global_sim's messages <-> the textile and dual-layer cores: finger states in (as the spheres
// the fingers may sweep), patch results in, patches and cloth frames out. No allocation once the
// messages and arrays have their capacity.

#include <array>
#include <cstdint>

#include "haptex/v1/cloth_frame.pb.h"
#include "haptex/v1/finger_states.pb.h"
#include "haptex/v1/local_patch.pb.h"
#include "libs/dual_layer/patch_cut.h"
#include "libs/dual_layer/patch_data.h"
#include "libs/dual_layer/patch_result.h"
#include "libs/textile/fabric_model.h"
#include "libs/textile/fabric_state.h"

namespace haptex::global_sim {

/// The sphere each finger may sweep over the next global step (dual_layer::SweptSphere); none
/// while the device is not ok.
std::array<dual_layer::FingerSphere, 2> FingerSpheres(const v1::FingerStates& states, double finger_reach_m,
                                                      double global_dt_s, double margin_m);

/// The patch as sent to local_contact (reusing `out`'s storage).
void ToMessage(const dual_layer::PatchData& patch, v1::LocalPatch* out);

/// Copies a received result into `out` (whose arrays keep their capacity). False when its arrays
/// do not match its ids or it is larger than the capacity: nothing is merged then.
bool CopyResult(const v1::PatchResult& result, dual_layer::PatchResultData* out);

/// Particles per ClothFrame datagram: about 24 kB of a draped cloth's positions (two bytes a
/// coordinate), 60 kB if every difference took the most a sint32 does (five).
inline constexpr int kClothFrameChunkParticles = 3900;
/// Chunk `chunk` of the cloth's positions as frame `frame_index`, with the patch cut at its step
/// (`patch` empty: none).
void FillClothFrame(const textile::FabricModel& model, const textile::FabricState& state,
                    const dual_layer::PatchRect& patch, std::uint64_t frame_index, int chunk, v1::ClothFrame* out);
/// Datagrams a frame of `particles` takes.
inline int ClothFrameChunks(int particles) {
  return (particles + kClothFrameChunkParticles - 1) / kClothFrameChunkParticles;
}

}  // namespace haptex::global_sim
