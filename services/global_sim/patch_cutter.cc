#include "services/global_sim/patch_cutter.h"

#include <algorithm>

namespace haptex::global_sim {

FingerSphere SweptSphere(const Eigen::Vector3d& position_W_m, const Eigen::Vector3d& predicted_W_m,
                         const Eigen::Vector3d& velocity_W_m_per_s, double finger_reach_m,
                         double global_dt_s, double margin_m) {
  FingerSphere s;
  s.present = position_W_m.allFinite() && predicted_W_m.allFinite() && velocity_W_m_per_s.allFinite();
  if (!s.present) return s;
  s.centre_W_m = position_W_m;
  s.radius_m = finger_reach_m + (predicted_W_m - position_W_m).norm() +
               velocity_W_m_per_s.norm() * global_dt_s + margin_m;
  return s;
}

PatchRect FindPatchRect(const textile::FabricModel& model, const textile::FabricState& state,
                        const std::array<FingerSphere, 2>& spheres) {
  const int nu = model.mesh.particles_warp(), nv = model.mesh.particles_weft();
  PatchRect r{nu, -1, nv, -1};
  for (int j = 0; j < nv; ++j) {
    for (int i = 0; i < nu; ++i) {
      const Eigen::Vector3d x = state.x(model.mesh.Index(i, j));
      for (const FingerSphere& s : spheres) {
        if (!s.present || (x - s.centre_W_m).squaredNorm() > s.radius_m * s.radius_m) continue;
        r.i0 = std::min(r.i0, i);
        r.i1 = std::max(r.i1, i);
        r.j0 = std::min(r.j0, j);
        r.j1 = std::max(r.j1, j);
      }
    }
  }
  if (r.empty()) return PatchRect{};
  r.i0 = std::max(0, r.i0 - 1);
  r.j0 = std::max(0, r.j0 - 1);
  r.i1 = std::min(nu - 1, r.i1 + 1);
  r.j1 = std::min(nv - 1, r.j1 + 1);
  // Start on a cell of even parity: GridMesh alternates each cell's diagonal by (i + j) parity,
  // so the patch then has the same triangles as the fabric it is cut from.
  if ((r.i0 + r.j0) % 2 != 0) r.i0 > 0 ? --r.i0 : --r.j0;
  // A patch needs at least 2 x 2 particles to have a triangle.
  if (r.i1 == r.i0) r.i1 < nu - 1 ? ++r.i1 : --r.i0;
  if (r.j1 == r.j0) r.j1 < nv - 1 ? ++r.j1 : --r.j0;
  return r;
}

void FillLocalPatch(const textile::FabricModel& model, const textile::FabricState& state,
                    const PatchRect& rect, std::uint64_t patch_id, std::uint64_t global_step,
                    double global_dt_s, v1::LocalPatch* out) {
  const int nu = model.mesh.particles_warp(), nv = model.mesh.particles_weft();
  out->set_patch_id(patch_id);
  out->set_global_step(global_step);
  out->set_global_time_s(state.time_s);
  out->set_global_dt_s(global_dt_s);
  out->clear_particle_ids();
  out->clear_rest_uv_m();
  out->clear_position_w_m();
  out->clear_velocity_w_m_per_s();
  out->clear_mass_kg();
  out->clear_is_border();
  out->clear_triangles();
  const int pu = rect.i1 - rect.i0 + 1;
  for (int j = rect.j0; j <= rect.j1; ++j) {
    for (int i = rect.i0; i <= rect.i1; ++i) {
      const int p = model.mesh.Index(i, j);
      out->add_particle_ids(static_cast<std::uint32_t>(p));
      const Eigen::Vector2d& uv = model.mesh.rest_uv_m(p);
      out->add_rest_uv_m(uv.x());
      out->add_rest_uv_m(uv.y());
      for (int k = 0; k < 3; ++k) out->add_position_w_m(state.x_W_m[3 * p + k]);
      for (int k = 0; k < 3; ++k) out->add_velocity_w_m_per_s(state.v_W_m_per_s[3 * p + k]);
      out->add_mass_kg(model.mass_kg[p]);
      const bool rect_edge = (i == rect.i0 && i > 0) || (i == rect.i1 && i < nu - 1) ||
                             (j == rect.j0 && j > 0) || (j == rect.j1 && j < nv - 1);
      const bool prescribed = state.mode[static_cast<std::size_t>(p)] != textile::ParticleMode::kFree;
      out->add_is_border(rect_edge || prescribed);
    }
  }
  // Triangles of the sub-grid in patch indices, as GridMesh splits each cell.
  for (const auto& t : model.mesh.triangles()) {
    std::array<std::uint32_t, 3> local{};
    bool inside = true;
    for (int k = 0; k < 3 && inside; ++k) {
      const int p = t[static_cast<std::size_t>(k)];
      const int i = p % nu, j = p / nu;
      inside = i >= rect.i0 && i <= rect.i1 && j >= rect.j0 && j <= rect.j1;
      local[static_cast<std::size_t>(k)] = static_cast<std::uint32_t>((i - rect.i0) + pu * (j - rect.j0));
    }
    if (!inside) continue;
    for (std::uint32_t v : local) out->add_triangles(v);
  }
}

}  // namespace haptex::global_sim
