#include "libs/dual_layer/patch_merge.h"

#include <Eigen/Core>

namespace haptex::dual_layer {

int MergePatchResult(const PatchResultData& r, int id_space, textile::FabricState* state, std::vector<int>* merged) {
  const int m = r.num_particles();
  if (r.x_W_m.size() != 3 * r.ids.size() || r.v_W_m_per_s.size() != 3 * r.ids.size() ||
      r.external_force_W_N.size() != 3 * r.ids.size()) {
    return -1;
  }
  ReleaseMerged(state, merged);  // a newer result replaces the last
  const int n = state->num_particles();
  int rejected = 0;
  for (int k = 0; k < m; ++k) {
    const auto p = static_cast<int>(r.ids[static_cast<std::size_t>(k)]);
    const Eigen::Vector3d x = Eigen::Map<const Eigen::Vector3d>(&r.x_W_m[3 * static_cast<std::size_t>(k)]);
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

MergedInterior::MergedInterior(int max_held_steps, int num_particles) : max_held_steps_(max_held_steps) {
  held_.reserve(static_cast<std::size_t>(num_particles));
  last_result_.reserve(static_cast<std::size_t>(num_particles));
}

int MergedInterior::Merge(const PatchResultData& result, int id_space, textile::FabricState* state) {
  const int rejected = MergePatchResult(result, id_space, state, &held_);
  if (rejected < 0) return rejected;
  last_result_.assign(held_.begin(), held_.end());
  steps_since_result_ = 0;
  result_since_step_ = true;
  return rejected;
}

void MergedInterior::HoldBeforeStep(textile::FabricState* state) {
  if (result_since_step_ || last_result_.empty() || steps_since_result_ >= max_held_steps_) return;
  // nothing moved them since the last step held them: they are where the last result put them
  for (int p : last_result_) {
    if (state->mode[static_cast<std::size_t>(p)] != textile::ParticleMode::kFree) continue;
    state->Fix(p);
    held_.push_back(p);
  }
  ++steps_held_again_;
}

void MergedInterior::ReleaseAfterStep(textile::FabricState* state) {
  ReleaseMerged(state, &held_);
  result_since_step_ = false;
  ++steps_since_result_;
}

const Eigen::VectorXd& TwoStepVelocity::Update(const Eigen::VectorXd& v_W_m_per_s) {
  if (last_.size() != v_W_m_per_s.size()) last_ = v_W_m_per_s;
  mean_ = 0.5 * (v_W_m_per_s + last_);
  last_ = v_W_m_per_s;
  return mean_;
}

}  // namespace haptex::dual_layer
