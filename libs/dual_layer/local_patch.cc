#include "libs/dual_layer/local_patch.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "libs/dual_layer/global_link_delay.h"
#include "libs/textile/fabric_model.h"

namespace haptex::dual_layer {

const contact::ContactOutput& LocalPatch::Tick(const contact::FingerInput& thumb, const contact::FingerInput& index) {
  const contact::ContactOutput& out = sim->Tick(thumb, index);
  force_sum_W_N += sim->solver().particle_force_W_N();
  ++ticks_since_result;
  return out;
}

std::unique_ptr<LocalPatch> BuildLocalPatch(const PatchData& data, const textile::FabricMaterial& material,
                                            const textile::ModelOptions& model_options,
                                            const textile::StepOptions& step,
                                            const contact::ContactOptions& contact_options, int particle_id_space) {
  const int n = data.num_particles;
  // Grid structure: u grows fastest; count the u values of the first row.
  int nu = 1;
  while (nu < n &&
         data.rest_uv_m[2 * static_cast<std::size_t>(nu)] > data.rest_uv_m[2 * static_cast<std::size_t>(nu - 1)])
    ++nu;
  if (nu < 2 || n % nu != 0 || n / nu < 2) {
    throw std::invalid_argument("LocalPatch " + std::to_string(data.patch_id) + ": not a grid rectangle");
  }
  const int nv = n / nu;
  const double u0 = data.rest_uv_m[0], v0 = data.rest_uv_m[1];
  const double du = data.rest_uv_m[2] - u0;
  const double dv = data.rest_uv_m[2 * static_cast<std::size_t>(nu) + 1] - v0;
  for (int j = 0; j < nv; ++j) {
    for (int i = 0; i < nu; ++i) {
      const auto k = static_cast<std::size_t>(i + nu * j);
      if (std::abs(data.rest_uv_m[2 * k] - (u0 + i * du)) > 1e-6 ||
          std::abs(data.rest_uv_m[2 * k + 1] - (v0 + j * dv)) > 1e-6) {
        throw std::invalid_argument("LocalPatch " + std::to_string(data.patch_id) +
                                    ": rest coordinates are not a regular grid");
      }
    }
  }
  textile::FabricModel model =
      textile::BuildFabricModel(material, {(nu - 1) * du, (nv - 1) * dv, nu, nv}, model_options);
  textile::FabricState state = textile::MakeRestState(model);
  const double border_velocity_weight = BorderVelocityWeight(data.link_round_trip_steps);
  for (int p = 0; p < n; ++p) {
    for (int k = 0; k < 3; ++k) {
      state.x_W_m[3 * p + k] = data.x_W_m[3 * static_cast<std::size_t>(p) + static_cast<std::size_t>(k)];
      state.v_W_m_per_s[3 * p + k] = data.v_W_m_per_s[3 * static_cast<std::size_t>(p) + static_cast<std::size_t>(k)];
    }
    state.anchor_W_m.segment<3>(3 * p) = state.x(p);
    if (data.border[static_cast<std::size_t>(p)]) state.Prescribe(p, border_velocity_weight * state.v(p));
  }
  auto rt = std::make_unique<LocalPatch>();
  rt->sim = std::make_unique<contact::PatchSimulation>(std::move(model), std::move(state), step, contact_options,
                                                       Eigen::Vector2d(u0, v0));
  rt->patch_id = data.patch_id;
  rt->global_step = data.global_step;
  rt->global_dt_s = data.global_dt_s;
  rt->global_id = data.ids;
  rt->local_of_global.assign(static_cast<std::size_t>(particle_id_space), -1);
  for (int p = 0; p < n; ++p) rt->local_of_global[data.ids[static_cast<std::size_t>(p)]] = p;
  rt->force_sum_W_N = Eigen::VectorXd::Zero(3 * n);
  std::array<int, 6> none{};
  none.fill(-1);
  rt->triangles_of.assign(static_cast<std::size_t>(n), none);
  const auto& tris = rt->sim->model().triangles;
  for (std::size_t t = 0; t < tris.size(); ++t) {
    auto& list = rt->triangles_of[static_cast<std::size_t>(tris[t].p[0])];
    for (int& slot : list) {
      if (slot < 0) {
        slot = static_cast<int>(t);
        break;
      }
    }
  }
  return rt;
}

int HandOff(const LocalPatch& old, LocalPatch* fresh) {
  textile::FabricState& to = fresh->sim->state();
  const textile::FabricState& from = old.sim->state();
  int carried = 0;
  const int n_old = static_cast<int>(old.global_id.size());
  for (int q = 0; q < n_old; ++q) {
    const int p = fresh->local_of_global[old.global_id[static_cast<std::size_t>(q)]];
    if (p < 0 || to.mode[static_cast<std::size_t>(p)] != textile::ParticleMode::kFree) continue;
    to.x(p) = from.x(q);
    to.v(p) = from.v(q);
    for (int f = 0; f < 2; ++f) {
      fresh->sim->solver().finger_contact(f).SetParticle(p, old.sim->solver().finger_contact(f).particle(q));
    }
    fresh->force_sum_W_N.segment<3>(3 * p) = old.force_sum_W_N.segment<3>(3 * q);
    ++carried;
  }
  // The PatchResult cadence is the global step's, not the patch's: the ticks since the last result
  // carry over, or a patch replaced before a global step's worth of ticks never reports and
  // global_sim steps with the patch interior free and without the contact forces that hold it.
  fresh->ticks_since_result = old.ticks_since_result;
  // Pinch samples: the same triangle (same global vertices, same order) in the new patch.
  const contact::PinchContact& old_pinch = old.sim->solver().pinch();
  contact::PinchContact& new_pinch = fresh->sim->solver().pinch();
  const int per = old_pinch.samples_per_triangle();
  const auto& old_tris = old.sim->model().triangles;
  const auto& new_tris = fresh->sim->model().triangles;
  for (int i = 0; i < old_pinch.num_samples(); i += per) {
    bool any = false;
    for (int k = 0; k < per; ++k) any = any || old_pinch.sample(i + k).active;
    if (!any) continue;
    const auto& ot = old_tris[static_cast<std::size_t>(i / per)].p;
    std::array<int, 3> mapped{};
    bool inside = true;
    for (int k = 0; k < 3 && inside; ++k) {
      mapped[static_cast<std::size_t>(k)] =
          fresh->local_of_global[old.global_id[static_cast<std::size_t>(ot[static_cast<std::size_t>(k)])]];
      inside = mapped[static_cast<std::size_t>(k)] >= 0;
    }
    if (!inside) continue;
    for (int t : fresh->triangles_of[static_cast<std::size_t>(mapped[0])]) {
      if (t < 0) break;
      const auto& nt = new_tris[static_cast<std::size_t>(t)].p;
      if (nt[1] != mapped[1] || nt[2] != mapped[2]) continue;
      for (int k = 0; k < per; ++k) new_pinch.SetSample(t * per + k, old_pinch.sample(i + k));
      break;
    }
  }
  fresh->sim->solver().ContinueFrom(old.sim->solver());
  return carried;
}

void FillPatchResult(std::uint64_t global_step, LocalPatch* patch, PatchResultData* out) {
  const textile::FabricState& s = patch->sim->state();
  out->Clear();
  out->patch_id = patch->patch_id;
  out->global_step = global_step;
  const double scale = patch->ticks_since_result > 0 ? 1.0 / patch->ticks_since_result : 0.0;
  for (std::size_t p = 0; p < patch->global_id.size(); ++p) {
    if (s.mode[p] != textile::ParticleMode::kFree) continue;
    out->ids.push_back(patch->global_id[p]);
    for (int k = 0; k < 3; ++k) {
      const auto i = static_cast<Eigen::Index>(3 * p) + k;
      out->x_W_m.push_back(s.x_W_m[i]);
      out->v_W_m_per_s.push_back(s.v_W_m_per_s[i]);
      out->external_force_W_N.push_back(scale * patch->force_sum_W_N[i]);
    }
  }
  out->local_ticks = static_cast<std::uint32_t>(patch->ticks_since_result);
  patch->force_sum_W_N.setZero();
  patch->ticks_since_result = 0;
}

}  // namespace haptex::dual_layer
