#include "services/global_sim/patch_merge.h"

#include <Eigen/Core>

namespace haptex::global_sim {

int MergePatchResult(const v1::PatchResult& r, int id_space, textile::FabricState* state,
                     std::vector<int>* merged) {
  const int m = r.particle_ids_size();
  if (r.position_w_m_size() != 3 * m || r.velocity_w_m_per_s_size() != 3 * m ||
      r.external_force_w_n_size() != 3 * m) {
    return -1;
  }
  ReleaseMerged(state, merged);  // a newer result replaces the last
  const int n = state->num_particles();
  int rejected = 0;
  for (int k = 0; k < m; ++k) {
    const auto p = static_cast<int>(r.particle_ids(k));
    const Eigen::Vector3d x(r.position_w_m(3 * k), r.position_w_m(3 * k + 1), r.position_w_m(3 * k + 2));
    if (p < 0 || p >= id_space || !x.allFinite()) {
      ++rejected;
      continue;
    }
    if (p >= n) continue;  // a refined particle: the local layer's own detail
    if (state->mode[static_cast<std::size_t>(p)] != textile::ParticleMode::kFree) continue;
    state->x(p) = x;
    state->Fix(p);
    merged->push_back(p);
  }
  return rejected;
}

void ReleaseMerged(textile::FabricState* state, std::vector<int>* merged) {
  for (int p : *merged) state->Free(p);
  merged->clear();
}

const Eigen::VectorXd& TwoStepVelocity::Update(const Eigen::VectorXd& v_W_m_per_s) {
  if (last_.size() != v_W_m_per_s.size()) last_ = v_W_m_per_s;
  mean_ = 0.5 * (v_W_m_per_s + last_);
  last_ = v_W_m_per_s;
  return mean_;
}

}  // namespace haptex::global_sim
