#include "libs/dual_layer/patch_cut.h"

#include <algorithm>
#include <array>

namespace haptex::dual_layer {

FingerSphere SweptSphere(const Eigen::Vector3d& position_W_m, const Eigen::Vector3d& predicted_W_m,
                         const Eigen::Vector3d& velocity_W_m_per_s, double finger_reach_m, double global_dt_s,
                         double margin_m) {
  FingerSphere s;
  s.present = position_W_m.allFinite() && predicted_W_m.allFinite() && velocity_W_m_per_s.allFinite();
  if (!s.present) return s;
  s.centre_W_m = position_W_m;
  s.radius_m =
      finger_reach_m + (predicted_W_m - position_W_m).norm() + velocity_W_m_per_s.norm() * global_dt_s + margin_m;
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

int PatchParticleCount(const PatchRect& rect, const RefinedGrid& refined) {
  if (rect.empty()) return 0;
  return ((rect.i1 - rect.i0) * refined.factor + 1) * ((rect.j1 - rect.j0) * refined.factor + 1);
}

void CutPatch(const textile::FabricModel& model, const textile::FabricState& state,
              const Eigen::VectorXd& velocity_W_m_per_s, const PatchRect& rect, std::uint64_t patch_id,
              std::uint64_t global_step, double global_dt_s, const RefinedGrid& refined, PatchData* out) {
  const int nu = model.mesh.particles_warp(), nv = model.mesh.particles_weft();
  const int f = refined.factor;
  out->Clear();
  out->patch_id = patch_id;
  out->global_step = global_step;
  out->global_time_s = state.time_s;
  out->global_dt_s = global_dt_s;
  // Refined grid points I in [i0 f, i1 f], J in [j0 f, j1 f]; f = 1 is the rectangle itself.
  const int I0 = rect.i0 * f, I1 = rect.i1 * f, J0 = rect.j0 * f, J1 = rect.j1 * f;
  const int pu = I1 - I0 + 1;
  const double area_density_kg_per_m2 =
      model.mass_kg.sum() / (model.mesh.rest_uv_m(model.mesh.Index(nu - 1, nv - 1)).x() *
                             model.mesh.rest_uv_m(model.mesh.Index(nu - 1, nv - 1)).y());
  const Eigen::Vector2d cell_m =
      model.mesh.rest_uv_m(model.mesh.Index(1, 1)) - model.mesh.rest_uv_m(model.mesh.Index(0, 0));
  const double fine_cell_area_m2 = cell_m.x() * cell_m.y() / (f * f);
  for (int J = J0; J <= J1; ++J) {
    for (int I = I0; I <= I1; ++I) {
      out->ids.push_back(refined.IdOf(I, J));
      const bool rect_edge = (I == I0 && rect.i0 > 0) || (I == I1 && rect.i1 < nu - 1) || (J == J0 && rect.j0 > 0) ||
                             (J == J1 && rect.j1 < nv - 1);
      if (refined.IsCoarse(I, J)) {
        const int p = model.mesh.Index(I / f, J / f);
        const Eigen::Vector2d& uv = model.mesh.rest_uv_m(p);
        out->rest_uv_m.push_back(uv.x());
        out->rest_uv_m.push_back(uv.y());
        for (int k = 0; k < 3; ++k) out->x_W_m.push_back(state.x_W_m[3 * p + k]);
        for (int k = 0; k < 3; ++k) out->v_W_m_per_s.push_back(velocity_W_m_per_s[3 * p + k]);
        out->mass_kg.push_back(f == 1 ? model.mass_kg[p] : 0.0);
        const bool prescribed = state.mode[static_cast<std::size_t>(p)] != textile::ParticleMode::kFree;
        out->border.push_back(rect_edge || prescribed ? 1 : 0);
      } else {
        // the cell (ci, cj) holding the point, and its place in it
        const int ci = std::min(I / f, nu - 2), cj = std::min(J / f, nv - 2);
        const double a = static_cast<double>(I - ci * f) / f, b = static_cast<double>(J - cj * f) / f;
        const std::array<int, 4> corner{model.mesh.Index(ci, cj), model.mesh.Index(ci + 1, cj),
                                        model.mesh.Index(ci, cj + 1), model.mesh.Index(ci + 1, cj + 1)};
        const std::array<double, 4> w{(1 - a) * (1 - b), a * (1 - b), (1 - a) * b, a * b};
        Eigen::Vector2d uv = Eigen::Vector2d::Zero();
        Eigen::Vector3d x = Eigen::Vector3d::Zero(), v = Eigen::Vector3d::Zero();
        bool all_prescribed = true;
        for (std::size_t c = 0; c < 4; ++c) {
          if (w[c] == 0.0) continue;
          uv += w[c] * model.mesh.rest_uv_m(corner[c]);
          x += w[c] * state.x(corner[c]);
          v += w[c] * velocity_W_m_per_s.segment<3>(3 * corner[c]);
          all_prescribed =
              all_prescribed && state.mode[static_cast<std::size_t>(corner[c])] != textile::ParticleMode::kFree;
        }
        out->rest_uv_m.push_back(uv.x());
        out->rest_uv_m.push_back(uv.y());
        for (int k = 0; k < 3; ++k) out->x_W_m.push_back(x[k]);
        for (int k = 0; k < 3; ++k) out->v_W_m_per_s.push_back(v[k]);
        out->mass_kg.push_back(0.0);
        out->border.push_back(rect_edge || all_prescribed ? 1 : 0);
      }
      if (f > 1) {
        // lumped from the refined cells around the point (a quarter of each)
        const int cells = (I > 0 && J > 0) + (I < refined.fine_u - 1 && J > 0) + (I > 0 && J < refined.fine_v - 1) +
                          (I < refined.fine_u - 1 && J < refined.fine_v - 1);
        out->mass_kg.back() = area_density_kg_per_m2 * fine_cell_area_m2 * 0.25 * cells;
      }
    }
  }
  out->num_particles = static_cast<int>(out->ids.size());
  // Triangles of the (refined) sub-grid in patch indices, split as GridMesh splits each cell; the
  // rectangle starts on an even cell, so the patch's triangles are the refined fabric's.
  for (int J = J0; J < J1; ++J) {
    for (int I = I0; I < I1; ++I) {
      const auto p00 = static_cast<std::uint32_t>((I - I0) + pu * (J - J0));
      const std::uint32_t p10 = p00 + 1, p01 = p00 + static_cast<std::uint32_t>(pu), p11 = p01 + 1;
      const std::array<std::uint32_t, 6> t = (I + J) % 2 == 0
                                                 ? std::array<std::uint32_t, 6>{p00, p10, p11, p00, p11, p01}
                                                 : std::array<std::uint32_t, 6>{p00, p10, p01, p10, p11, p01};
      for (std::uint32_t k : t) out->triangles.push_back(k);
    }
  }
}

}  // namespace haptex::dual_layer
