#pragma once
// The pinch's sample points (PinchContact, paper 5.4), four samples of a triangle at a time:
// which are active and with what spring, and Coulomb's law with the springs' lumping.
//
// A sample is active while it lies in both fingers (within their radius plus the fabric). Its
// spring is the full one deeper than the edge ramp in both, ramped down to 0 at the edge. Each
// active sample has a spring k towards its ideal position on the contact plane; it sticks while
// k |q - ideal| is within mu_s (mu_d once sliding) of its share of the grip, else its ideal
// position trails the frictionless point q at mu_d of that share. Its spring w_m k (ideal - q) reaches corner
// m of its triangle (q = sum_m w_m x_m).
//
// Samples are stored as structures of arrays, triangle-major, each triangle's samples padded to
// whole 4-lane chunks (pad lanes have weight 0 and no spring). A lane is active when its spring
// k > 0. The per-sample formulas are those of the scalar law (coulomb_friction.h states it); the
// sums over a triangle's samples are formed lane-wise, so they round differently from a
// sample-by-sample sum. An AVX2 build and a portable build do the same IEEE operations in the same
// order: identical results on any CPU.

#include <array>
#include <cstdint>

namespace haptex::contact::internal {

/// A particle's sums over the samples on it, in the contact frame C: sum of w k (ideal - q) [N]
/// and sum of w k [N/m]. 32 bytes, aligned: one 4-wide add per triangle corner.
struct alignas(32) PinchParticleSums {
  double kd_x_N = 0.0, kd_y_N = 0.0, kd_z_N = 0.0;
  double k_N_per_m = 0.0;
};

/// The samples' weights and springs, fixed for a patch.
struct PinchSampleLayout {
  int chunks = 1;                        ///< 4-lane chunks per triangle
  const double* w = nullptr;             ///< [chunk][corner][lane]: barycentric weight of the lane's sample
  const double* k_full_lanes = nullptr;  ///< [chunk][lane]: the full spring [N/m] (0 on pad lanes)
  const double* w_sum_full = nullptr;    ///< [corner]: sum of the weights over all samples
  double k_full_N_per_m = 0.0;
  const double* wk_full = nullptr;  ///< [chunk][corner][lane]: w times k_full_lanes
};

/// A capsule's axis in the contact frame C: from a along ab (inv_len2 = 1 / |ab|^2, 0 for a sphere).
struct PinchAxis {
  double a[3] = {0.0, 0.0, 0.0};
  double ab[3] = {0.0, 0.0, 0.0};
  double inv_len2 = 0.0;
};

/// Where the particles are this tick: their positions x_W (3 per particle), the contact frame C
/// (origin and rotation, R_CW row-major) and the fingers' axes in C.
struct PinchLocateInput {
  const double* x_W_m = nullptr;
  int num_particles = 0;
  double origin_W_m[3] = {0.0, 0.0, 0.0};
  double R_CW[9] = {1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0};
  PinchAxis thumb, index;
  double reach2_m2 = 0.0;  ///< near the intersection: within this squared distance of the origin
  // In the intersection for certain below both in_*2, certainly not above an out_*2.
  double in_thumb2 = 0.0, in_index2 = 0.0, out_thumb2 = 0.0, out_index2 = 0.0;
  /// Deeper than the edge ramp in both fingers: below both (a triangle whose corners all are
  /// holds all its samples at the full spring).
  double full_thumb2 = 0.0, full_index2 = 0.0;
};

/// Whether a particle lies in both fingers.
enum class PinchOwned : std::uint8_t { kNo = 0, kYes = 1, kExactTest = 2 };

/// Per particle (arrays padded to a multiple of 4 particles; x_C 4 doubles per particle).
struct PinchParticleArrays {
  double* x_C_m = nullptr;        ///< position in C, (x, y, z, pad)
  double* d2_thumb_m2 = nullptr;  ///< squared distance to the thumb's axis
  double* d2_index_m2 = nullptr;
  std::uint8_t* near = nullptr;    ///< near the intersection (only its triangles can hold samples)
  std::uint8_t* deep = nullptr;    ///< below both full_*2 (false for a NaN distance)
  PinchOwned* owned = nullptr;     ///< kNo for particles not near
  std::uint8_t* beyond = nullptr;  ///< bit 0: above out_thumb2, bit 1: above out_index2 (certainly outside)
};

/// Fills the particle arrays.
void LocatePinchParticles(const PinchLocateInput& in, const PinchParticleArrays& out, bool avx2);

/// The triangles a kernel works on, and where their corners are.
struct PinchTriangleList {
  const double* x_C_m = nullptr;                   ///< 4 per particle: positions in C (PinchParticleArrays)
  const std::array<int, 3>* triangle_p = nullptr;  ///< corners of each triangle of the patch
  const int* triangles = nullptr;                  ///< the triangles, ascending
  int num_triangles = 0;
};

/// A triangle's entry in PinchClassifyInput::deep: deep means every corner lies deeper than the
/// ramp in both fingers (all samples at the full spring); unchanged, that its samples already are
/// all at the full spring (the last classification's kAllFull), so the kernel only counts it.
constexpr std::uint8_t kPinchNotDeep = 0, kPinchDeep = 1, kPinchDeepUnchanged = 2;

/// What the classification needs this tick.
struct PinchClassifyInput {
  PinchTriangleList list;              ///< the triangles to classify
  const std::uint8_t* deep = nullptr;  ///< per entry: kPinchNotDeep, kPinchDeep or kPinchDeepUnchanged
  PinchAxis thumb, index;
  double radius_thumb_m = 0.0, radius_index_m = 0.0;  ///< reach of the pinch
  double edge_ramp_m = 0.0;
  // Thresholds on squared distances with a relative margin for rounding (PinchContact): certainly
  // deeper than the ramp below full_*2, certainly outside above out_*2.
  double full_thumb2 = 0.0, full_index2 = 0.0, out_thumb2 = 0.0, out_index2 = 0.0;
};

/// Per classified triangle: no active sample, some, or all at the full spring.
enum class PinchTriangleHold : std::uint8_t { kNone = 0, kSome = 1, kAllFull = 2 };

struct PinchClassifyTotals {
  int active_not_full = 0;          ///< active samples in triangles not all at the full spring
  double k_not_full_N_per_m = 0.0;  ///< the sum of their springs
  int all_full_triangles = 0;
};

/// What the law needs this tick.
struct PinchFrictionInput {
  PinchTriangleList list;                    ///< the triangles with an active sample
  const std::uint8_t* full = nullptr;        ///< per entry: every sample active at the full spring
  double normal_per_stiffness_m = 0.0;       ///< a sample's share of the grip per N/m of its spring
  double mu_static = 0.0, mu_dynamic = 0.0;  ///< per sample: both faces grip (2 mu)
};

/// The samples' state, per lane (triangle-major, padded).
struct PinchSampleArrays {
  double* ideal_x_C_m = nullptr;
  double* ideal_y_C_m = nullptr;
  double* k_N_per_m = nullptr;   ///< this tick's spring; 0: inactive
  long long* sliding = nullptr;  ///< -1 sliding, 0 sticking (kept while inactive)
};

struct PinchFrictionTotals {
  double k_ideal_x_N = 0.0, k_ideal_y_N = 0.0;  ///< sum of k ideal over the active samples
  int sliding = 0;                              ///< active samples sliding
};

/// Sets each sample's spring (0: inactive) for the listed triangles; a sample that becomes
/// active sticks where it is (its ideal position is its point, not sliding). `hold` gets one
/// entry per triangle. Entries marked deep hold every sample at the full spring (the distance to
/// an axis is convex: no point is farther than the farthest corner).
PinchClassifyTotals ClassifyPinchSamples(const PinchSampleLayout& layout, const PinchClassifyInput& in,
                                         const PinchSampleArrays& samples, PinchTriangleHold* hold, bool avx2);

/// Applies the law to every sample of the listed triangles (updating ideal positions and sliding
/// flags) and adds their springs to `sums` and their weights to `w_sums` (per particle, in
/// triangle order). A grip of 0 leaves no friction: the ideal positions follow q.
/// `avx2` picks the AVX2 build (only where the CPU has it); the results are the same.
PinchFrictionTotals ApplyPinchFriction(const PinchSampleLayout& layout, const PinchFrictionInput& in,
                                       const PinchSampleArrays& samples, PinchParticleSums* sums, double* w_sums,
                                       bool avx2);

}  // namespace haptex::contact::internal
