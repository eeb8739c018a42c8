#pragma once
// Cuts the local patch for local_contact (paper section 4): the grid rectangle around every
// particle inside a finger's bounding sphere over the next global step, plus one ring of border
// particles that local_contact holds where global_sim puts them.

#include <array>
#include <cstdint>

#include <Eigen/Core>

#include "haptex/v1/local_patch.pb.h"
#include "libs/textile/fabric_model.h"
#include "libs/textile/fabric_state.h"
#include "services/common/refined_grid.h"

namespace haptex::global_sim {

struct FingerSphere {
  bool present = false;
  Eigen::Vector3d centre_W_m{Eigen::Vector3d::Zero()};
  double radius_m = 0.0;
};

/// The sphere a finger may sweep over the next global step: its reach (radius plus half the
/// capsule), the distance to its predicted position, its speed times the step, and the scene's
/// patch margin.
FingerSphere SweptSphere(const Eigen::Vector3d& position_W_m, const Eigen::Vector3d& predicted_W_m,
                         const Eigen::Vector3d& velocity_W_m_per_s, double finger_reach_m,
                         double global_dt_s, double margin_m);

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

/// Fills `out` (reusing its storage) with the rectangle's particles in grid order (i fastest),
/// their state, and triangles. A particle is border when it lies on the rectangle's edge but not
/// on the fabric's own edge (there the fabric is free), or when global_sim prescribes it.
/// With `refined` of 1 or more levels, every cell of the rectangle is split into factor x factor
/// cells (ids from `refined`); a new particle's rest coordinates, position and velocity are the
/// bilinear blend of its cell's corners, and it is border when it lies on the rectangle's edge or
/// every corner it blends is prescribed (a fixed edge stays fixed between its particles).
void FillLocalPatch(const textile::FabricModel& model, const textile::FabricState& state,
                    const PatchRect& rect, std::uint64_t patch_id, std::uint64_t global_step,
                    double global_dt_s, const services::RefinedGrid& refined, v1::LocalPatch* out);
/// As above, with the particles' velocities (3n) taken from `velocity_W_m_per_s` instead of the
/// state's (global_sim sends the velocity over its last two steps: patch_merge.h).
void FillLocalPatch(const textile::FabricModel& model, const textile::FabricState& state,
                    const Eigen::VectorXd& velocity_W_m_per_s, const PatchRect& rect, std::uint64_t patch_id,
                    std::uint64_t global_step, double global_dt_s, const services::RefinedGrid& refined,
                    v1::LocalPatch* out);

}  // namespace haptex::global_sim
