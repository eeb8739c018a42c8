#include "libs/textile/external_force.h"

#include <stdexcept>

namespace haptex::textile {

void AddExternalForces(const FabricModel& model, const FabricState& state, ForceSink* sink) {
  const Eigen::Vector3d& g = model.options.gravity_m_per_s2;
  for (int p = 0; p < model.num_particles; ++p) {
    sink->AddForce(p, model.mass_kg[p] * g + state.external_force_W_N.segment<3>(3 * p));
  }
}

void AddEdgeLoad(const FabricModel& model, const std::vector<int>& chain, const Eigen::Vector3d& total_W_N,
                 FabricState* state) {
  if (chain.empty()) throw std::invalid_argument("AddEdgeLoad: empty particle chain");
  for (int p : chain) {
    if (p < 0 || p >= model.num_particles) {
      throw std::invalid_argument("AddEdgeLoad: particle index out of range");
    }
  }
  if (chain.size() == 1) {
    state->external_force_W_N.segment<3>(3 * chain[0]) += total_W_N;
    return;
  }
  std::vector<double> share(chain.size(), 0.0);
  double total_length = 0.0;
  for (std::size_t k = 0; k + 1 < chain.size(); ++k) {
    const double len = (model.mesh.rest_uv_m(chain[k + 1]) - model.mesh.rest_uv_m(chain[k])).norm();
    share[k] += 0.5 * len;
    share[k + 1] += 0.5 * len;
    total_length += len;
  }
  if (!(total_length > 0.0)) throw std::invalid_argument("AddEdgeLoad: chain has zero length");
  for (std::size_t k = 0; k < chain.size(); ++k) {
    state->external_force_W_N.segment<3>(3 * chain[k]) += (share[k] / total_length) * total_W_N;
  }
}

void SetPointLoad(int p, const Eigen::Vector3d& force_W_N, FabricState* state) {
  state->external_force_W_N.segment<3>(3 * p) = force_W_N;
}

}  // namespace haptex::textile
