#pragma once
// Cutting the local patch (paper section 4): the grid rectangle around every particle inside a
// finger's bounding sphere over the next global step, plus one ring of border particles that the
// local layer holds where the global layer puts them, optionally refined.

#include <array>
#include <cstdint>

#include <Eigen/Core>

#include "libs/dual_layer/patch_data.h"
#include "libs/dual_layer/refined_grid.h"
#include "libs/textile/fabric_model.h"
#include "libs/textile/fabric_state.h"

namespace haptex::dual_layer {

struct FingerSphere {
  bool present = false;
  Eigen::Vector3d centre_W_m{Eigen::Vector3d::Zero()};
  double radius_m = 0.0;
};

/// The sphere a finger may sweep over the next global step: its reach (radius plus half the
/// capsule), the distance to its predicted position, its speed times the step, and the scene's
/// patch margin.
FingerSphere SweptSphere(const Eigen::Vector3d& position_W_m, const Eigen::Vector3d& predicted_W_m,
                         const Eigen::Vector3d& velocity_W_m_per_s, double finger_reach_m, double global_dt_s,
                         double margin_m);

/// Grid index rectangle [i0, i1] x [j0, j1] of a patch.
struct PatchRect {
  int i0 = 0, i1 = -1, j0 = 0, j1 = -1;
  bool empty() const { return i1 < i0 || j1 < j0; }
  int count() const { return empty() ? 0 : (i1 - i0 + 1) * (j1 - j0 + 1); }
};

/// The rectangle covering every particle inside a sphere, grown by one border ring (clamped to
/// the fabric) and to an even-parity corner (so its triangles are the fabric's). Empty when no
/// particle is inside.
PatchRect FindPatchRect(const textile::FabricModel& model, const textile::FabricState& state,
                        const std::array<FingerSphere, 2>& spheres);

/// Particles of the patch `rect` gives with `refined`'s levels (what CutPatch fills).
int PatchParticleCount(const PatchRect& rect, const RefinedGrid& refined);

/// Fills `out` (reusing its storage) with the rectangle's particles in grid order (i fastest),
/// their state, and triangles. A particle is border when it lies on the rectangle's edge but not
/// on the fabric's own edge (there the fabric is free), or when the global layer prescribes it.
/// With `refined` of 1 or more levels, every cell of the rectangle is split into factor x factor
/// cells (ids from `refined`); a new particle's rest coordinates, position and velocity are the
/// bilinear blend of its cell's corners, and it is border when it lies on the rectangle's edge or
/// every corner it blends is prescribed (a fixed edge stays fixed between its particles).
/// The particles' velocities (3n) come from `velocity_W_m_per_s` (the global layer sends the
/// velocity over its last two steps: patch_merge.h).
void CutPatch(const textile::FabricModel& model, const textile::FabricState& state,
              const Eigen::VectorXd& velocity_W_m_per_s, const PatchRect& rect, std::uint64_t patch_id,
              std::uint64_t global_step, double global_dt_s, const RefinedGrid& refined, PatchData* out);

}  // namespace haptex::dual_layer
