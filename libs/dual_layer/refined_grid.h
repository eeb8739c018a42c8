#pragma once
// Particle ids of refined local patches (model.patch_refinement): the whole fabric's grid with
// every cell split 2^levels x 2^levels times. A particle on an original grid point keeps its
// fabric id; the others get (fabric particles + their index in the refined grid), so every patch
// names the same refined particle alike and a hand-off can carry it.

#include <cstdint>
#include <stdexcept>

namespace haptex::dual_layer {

struct RefinedGrid {
  int levels = 0;
  int factor = 1;                  ///< 2^levels refined cells per original cell and direction
  int coarse_u = 0, coarse_v = 0;  ///< the fabric's particles per row and column
  int fine_u = 0, fine_v = 0;      ///< the refined grid's

  int coarse_count() const { return coarse_u * coarse_v; }
  bool IsCoarse(int I, int J) const { return I % factor == 0 && J % factor == 0; }
  /// Id of refined grid point (I, J).
  std::uint32_t IdOf(int I, int J) const {
    if (IsCoarse(I, J)) return static_cast<std::uint32_t>(I / factor + coarse_u * (J / factor));
    return static_cast<std::uint32_t>(coarse_count() + I + fine_u * J);
  }
  /// Every id is below this.
  std::uint32_t id_space() const {
    return static_cast<std::uint32_t>(coarse_count() + (levels > 0 ? fine_u * fine_v : 0));
  }
};

/// @throws std::invalid_argument for levels outside [0, 4] or a grid under 2 x 2.
inline RefinedGrid MakeRefinedGrid(int particles_u, int particles_v, int levels) {
  if (levels < 0 || levels > 4) throw std::invalid_argument("patch refinement must be 0..4 levels");
  if (particles_u < 2 || particles_v < 2) throw std::invalid_argument("a fabric grid needs 2 x 2 particles");
  RefinedGrid g;
  g.levels = levels;
  g.factor = 1 << levels;
  g.coarse_u = particles_u;
  g.coarse_v = particles_v;
  g.fine_u = (particles_u - 1) * g.factor + 1;
  g.fine_v = (particles_v - 1) * g.factor + 1;
  return g;
}

}  // namespace haptex::dual_layer
