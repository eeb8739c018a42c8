#pragma once
// Procedural woven-fabric surfaces (docs/tactile.md section 5.1): the virtual tactile fabric
// when no scan of the real fabric exists.

#include <cstdint>

#include <Eigen/Core>

#include "libs/tactile/height_map.h"

namespace haptex::tactile {

enum class WeavePattern {
  kPlain,  ///< 1/1: each thread alternates over/under.
  kTwill,  ///< twill_over/twill_under (e.g. 2/1, 3/1), shifted by one thread per pick.
  kSatin,  ///< satin_repeat-end satin with step satin_step (warp-faced).
};

/// Weave construction. Warp threads run along v (y) and repeat along u (x) with warp_pitch_m;
/// weft threads run along u and repeat along v with weft_pitch_m.
struct WeaveParams {
  WeavePattern pattern = WeavePattern::kPlain;
  double warp_pitch_m = 0.4e-3;
  double weft_pitch_m = 0.4e-3;
  double yarn_diameter_m = 0.25e-3;  ///< flattened yarn width is yarn_diameter_m * flattening
  double flattening = 1.4;
  int twill_over = 2;
  int twill_under = 1;
  int satin_repeat = 5;
  int satin_step = 2;
  /// Target KES SMD [um]: the generated map is scaled so that its mean absolute deviation equals it.
  double smd_um = 5.0;
  /// Yarn hairiness: white noise smoothed over ~2 pixels, RMS relative to the SMD. 0 disables.
  double hairiness_fraction = 0.0;
  std::uint64_t seed = 1;
  double pixel_size_m = 20e-6;
  int size_x = 256;
  int size_y = 256;
};

/// Generates the height map. @throws std::invalid_argument on non-positive sizes or pitches.
HeightMap GenerateWeave(const WeaveParams& params);

/// The weave's smallest translational cell, as columns [a b] in metres (not reduced): what the
/// periodicity analysis should recover from GenerateWeave's output.
Eigen::Matrix2d WeaveLatticeBasis(const WeaveParams& params);

/// True where the warp thread i passes over the weft thread j.
bool WarpOver(const WeaveParams& params, int i, int j);

}  // namespace haptex::tactile
