#include "libs/contact/pinch_sample_lanes.h"

#include <algorithm>
#include <bit>
#include <cstdint>

#include "libs/base/cpu_features.h"
#include "libs/base/demand.h"
#include "libs/base/lanes.h"

// The kernels are built twice (portable and AVX2) from the same source: see lanes.h.

namespace haptex::contact::internal {
namespace {

using base::lanes::Any;
using base::lanes::LaneSums;
using base::lanes::M4;
using base::lanes::Splat;
using base::lanes::Sqrt;
using base::lanes::Transpose;
using base::lanes::V4;
using base::lanes::Where;

// Sum of the four lanes of a count (masks subtracted: +1 per set lane).
HAPTEX_LANES_INLINE int LaneCount(M4 count) { return static_cast<int>((count[0] + count[1]) + (count[2] + count[3])); }

HAPTEX_LANES_INLINE V4 Load(const double* p) {
  V4 v;
  __builtin_memcpy(&v, p, sizeof v);
  return v;
}
HAPTEX_LANES_INLINE void Store(V4 v, double* p) { __builtin_memcpy(p, &v, sizeof v); }
HAPTEX_LANES_INLINE M4 LoadMask(const long long* p) {
  M4 m;
  __builtin_memcpy(&m, p, sizeof m);
  return m;
}
HAPTEX_LANES_INLINE void StoreMask(M4 m, long long* p) { __builtin_memcpy(p, &m, sizeof m); }

// Bit j set where lane j of the mask is.
HAPTEX_LANES_INLINE int LaneBits(M4 m) {
#ifdef __SSE2__
  using M2 = long long __attribute__((vector_size(16)));
  return _mm_movemask_pd(std::bit_cast<__m128d>(M2(__builtin_shufflevector(m, m, 0, 1)))) |
         _mm_movemask_pd(std::bit_cast<__m128d>(M2(__builtin_shufflevector(m, m, 2, 3)))) << 2;
#else
  return (m[0] & 1) | (m[1] & 2) | (m[2] & 4) | (m[3] & 8);
#endif
}
// Four bytes, byte j 1 where lane j of the mask is set (as a word: byte-wise sums and products
// by 2 do not carry, whatever the byte order).
alignas(4) constexpr std::uint8_t kLaneBytes[16][4] = {
    {0, 0, 0, 0}, {1, 0, 0, 0}, {0, 1, 0, 0}, {1, 1, 0, 0}, {0, 0, 1, 0}, {1, 0, 1, 0}, {0, 1, 1, 0}, {1, 1, 1, 0},
    {0, 0, 0, 1}, {1, 0, 0, 1}, {0, 1, 0, 1}, {1, 1, 0, 1}, {0, 0, 1, 1}, {1, 0, 1, 1}, {0, 1, 1, 1}, {1, 1, 1, 1}};
HAPTEX_LANES_INLINE std::uint32_t LaneBytes(M4 m) {
  std::uint32_t bytes;
  __builtin_memcpy(&bytes, kLaneBytes[LaneBits(m)], sizeof bytes);
  return bytes;
}
template <typename T>
HAPTEX_LANES_INLINE void StoreBytes(std::uint32_t bytes, T* p) {
  static_assert(sizeof(T) == 1);
  __builtin_memcpy(p, &bytes, sizeof bytes);
}

HAPTEX_LANES_INLINE V4 Min(V4 a, V4 b) { return a < b ? a : b; }
HAPTEX_LANES_INLINE V4 Max(V4 a, V4 b) { return a > b ? a : b; }

// Squared distances of four points q (per axis) to a capsule axis: the clamped projection onto it.
HAPTEX_LANES_INLINE V4 Distance2(const PinchAxis& axis, const V4 q[3]) {
  V4 aq[3];
  HAPTEX_UNROLL
  for (int i = 0; i < 3; ++i) aq[i] = q[i] - axis.a[i];
  const V4 along = (aq[0] * axis.ab[0] + aq[1] * axis.ab[1] + aq[2] * axis.ab[2]) * axis.inv_len2;
  const V4 t = Min(Max(along, Splat(0.0)), Splat(1.0));
  V4 r[3];
  HAPTEX_UNROLL
  for (int i = 0; i < 3; ++i) r[i] = aq[i] - t * axis.ab[i];
  return r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
}

HAPTEX_LANES_INLINE void LocateKernel(const PinchLocateInput& in, const PinchParticleArrays& out) {
  const int n = in.num_particles;
  for (int p0 = 0; p0 < n; p0 += 4) {
    V4 x_W[3] = {};  // per axis
    if (p0 + 4 <= n) {
      // Four particles' 12 coordinates, loaded whole and regrouped by axis.
      const double* x = in.x_W_m + 3 * p0;
      const V4 a = Load(x), b = Load(x + 4), c = Load(x + 8);  // x0 y0 z0 x1 | y1 z1 x2 y2 | z2 x3 y3 z3
      x_W[0] = __builtin_shufflevector(__builtin_shufflevector(a, b, 0, 3, 6, 7), c, 0, 1, 2, 5);
      x_W[1] = __builtin_shufflevector(__builtin_shufflevector(a, b, 1, 4, 7, 7), c, 0, 1, 2, 6);
      x_W[2] = __builtin_shufflevector(__builtin_shufflevector(a, b, 2, 5, 5, 5), c, 0, 1, 4, 7);
    } else {
      // The last repeated past the end: its lanes land in the arrays' padding.
      const double* x[4];
      HAPTEX_UNROLL
      for (int j = 0; j < 4; ++j) x[j] = in.x_W_m + 3 * std::min(p0 + j, n - 1);
      HAPTEX_UNROLL
      for (int i = 0; i < 3; ++i) x_W[i] = V4{x[0][i], x[1][i], x[2][i], x[3][i]};
    }
    V4 rel[3];
    HAPTEX_UNROLL
    for (int i = 0; i < 3; ++i) rel[i] = x_W[i] - in.origin_W_m[i];
    V4 q[3];
    HAPTEX_UNROLL
    for (int i = 0; i < 3; ++i) {
      q[i] = in.R_CW[3 * i] * rel[0] + in.R_CW[3 * i + 1] * rel[1] + in.R_CW[3 * i + 2] * rel[2];
    }
    const V4 dt2 = Distance2(in.thumb, q), di2 = Distance2(in.index, q);
    const M4 near = rel[0] * rel[0] + rel[1] * rel[1] + rel[2] * rel[2] < in.reach2_m2;
    const M4 in_both = near & (dt2 < in.in_thumb2) & (di2 < in.in_index2);
    const M4 maybe = near & ~in_both & ~((dt2 > in.out_thumb2) | (di2 > in.out_index2));
    const M4 deep = (dt2 < in.full_thumb2) & (di2 < in.full_index2);
    const std::size_t up = static_cast<std::size_t>(p0);
    Store(dt2, out.d2_thumb_m2 + up);
    Store(di2, out.d2_index_m2 + up);
    V4 xc[4];
    const V4 rows[4] = {q[0], q[1], q[2], Splat(0.0)};
    Transpose(rows, xc);
    HAPTEX_UNROLL
    for (int j = 0; j < 4; ++j) Store(xc[j], out.x_C_m + 4 * (up + static_cast<std::size_t>(j)));
    // The flags of the four, as bytes 0/1 (owned: kNo, kYes or kExactTest), four at a time.
    StoreBytes(LaneBytes(near), out.near + up);
    StoreBytes(LaneBytes(deep), out.deep + up);
    static_assert(static_cast<int>(PinchOwned::kYes) == 1 && static_cast<int>(PinchOwned::kExactTest) == 2);
    StoreBytes(LaneBytes(in_both) + 2 * LaneBytes(maybe), out.owned + up);
    StoreBytes(LaneBytes(dt2 > in.out_thumb2) + 2 * LaneBytes(di2 > in.out_index2), out.beyond + up);
  }
}

// Entry a of the list: its triangle, and its corners' positions in x.
HAPTEX_LANES_INLINE int Corners(const PinchTriangleList& list, int a, const double* x[3]) {
  const int t = list.triangles[a];
  const std::array<int, 3>& p = list.triangle_p[t];
  HAPTEX_UNROLL
  for (int m = 0; m < 3; ++m) x[m] = list.x_C_m + 4 * p[static_cast<std::size_t>(m)];
  return t;
}

// kChunks: the chunks per triangle as a constant (0: layout.chunks), so that one-chunk
// triangles (the default, 2 samples per edge) keep every vector in a register.
template <int kChunks>
HAPTEX_LANES_INLINE PinchClassifyTotals ClassifyKernel(const PinchSampleLayout& layout, const PinchClassifyInput& in,
                                                       const PinchSampleArrays& s, PinchTriangleHold* hold) {
  const int chunks = kChunks > 0 ? kChunks : layout.chunks;
  const double k_full = layout.k_full_N_per_m;
  const bool ramped = in.edge_ramp_m > 0.0;
  PinchClassifyTotals totals;
  M4 active_count = M4{0, 0, 0, 0};  // minus the sum of the active masks (not-full triangles)
  for (int a = 0; a < in.list.num_triangles; ++a) {
    if (in.deep[a] == kPinchDeepUnchanged) {  // its springs stay, none starts
      hold[a] = PinchTriangleHold::kAllFull;
      ++totals.all_full_triangles;
      continue;
    }
    const double* x[3];  // corners in C, broadcast where used
    const int t = Corners(in.list, a, x);
    const bool deep = in.deep[a] != kPinchNotDeep;
    M4 any_active = M4{0, 0, 0, 0}, all_full = ~M4{0, 0, 0, 0};
    V4 k_sum = Splat(0.0);
    M4 count = M4{0, 0, 0, 0};
    for (int c = 0; c < chunks; ++c) {
      const std::size_t lane0 =
          4 * (static_cast<std::size_t>(t) * static_cast<std::size_t>(chunks) + static_cast<std::size_t>(c));
      const double* wc = layout.w + 12 * c;
      const V4 w[3] = {Load(wc), Load(wc + 4), Load(wc + 8)};
      const V4 k_full_lanes = Load(layout.k_full_lanes + 4 * c);
      const M4 real = k_full_lanes > 0.0;
      V4 q[3];
      HAPTEX_UNROLL
      for (int i = 0; i < 3; ++i) q[i] = w[0] * x[0][i] + w[1] * x[1][i] + w[2] * x[2][i];  // broadcasts
      V4 k = k_full_lanes;
      if (!deep) {
        const V4 dt2 = Distance2(in.thumb, q);
        if (!Any(real & ~(dt2 > in.out_thumb2))) {
          k = Splat(0.0);  // every sample certainly outside the thumb: the index does not matter
        } else {
          const V4 di2 = Distance2(in.index, q);
          const M4 outside = dt2 > in.out_thumb2 || di2 > in.out_index2;  // certainly, whatever the rounding
          const M4 full = dt2 < in.full_thumb2 && di2 < in.full_index2;
          if (Any(real & ~outside & ~full)) {
            // Near an edge: the depth in both decides.
            const V4 depth = Min(in.radius_thumb_m - Sqrt(dt2), in.radius_index_m - Sqrt(di2));
            const V4 ramp_k = ramped ? k_full * Min(Splat(1.0), depth / in.edge_ramp_m) : Splat(k_full);
            const M4 edge_inside = depth > 0.0 && ramp_k > 0.0;
            k = outside ? Splat(0.0) : (full ? k_full_lanes : Where(edge_inside, ramp_k));
            k = Where(real, k);
          } else {
            k = Where(real & ~outside & full, k_full_lanes);  // the same without the square roots
          }
        }
        all_full &= ~real | (k == k_full_lanes);
      }
      const M4 active = k > 0.0;
      const M4 start = active & ~(Load(s.k_N_per_m + lane0) > 0.0);
      if (Any(start)) {
        Store(start ? q[0] : Load(s.ideal_x_C_m + lane0), s.ideal_x_C_m + lane0);
        Store(start ? q[1] : Load(s.ideal_y_C_m + lane0), s.ideal_y_C_m + lane0);
        StoreMask(LoadMask(s.sliding + lane0) & ~start, s.sliding + lane0);
      }
      Store(k, s.k_N_per_m + lane0);
      any_active |= active;
      k_sum += k;
      count -= active;
    }
    if (deep || !Any(~all_full)) {
      hold[a] = PinchTriangleHold::kAllFull;
      ++totals.all_full_triangles;
    } else if (Any(any_active)) {
      hold[a] = PinchTriangleHold::kSome;
      const V4 sums = LaneSums(k_sum, Splat(0.0), Splat(0.0), Splat(0.0));
      totals.k_not_full_N_per_m += sums[0];
      active_count += count;
    } else {
      hold[a] = PinchTriangleHold::kNone;
    }
  }
  totals.active_not_full = LaneCount(active_count);
  return totals;
}

template <int kChunks>
HAPTEX_LANES_INLINE PinchFrictionTotals FrictionKernel(const PinchSampleLayout& layout, const PinchFrictionInput& in,
                                                       const PinchSampleArrays& s, PinchParticleSums* sums,
                                                       double* w_sums) {
  const double gps = in.normal_per_stiffness_m;
  const double mu_s = in.mu_static, mu_d = in.mu_dynamic;
  const bool loaded = gps > 0.0;
  const int chunks = kChunks > 0 ? kChunks : layout.chunks;
  V4 k_ideal_x = Splat(0.0), k_ideal_y = Splat(0.0);
  M4 sliding_count = M4{0, 0, 0, 0};  // minus the sum of the sliding masks
  for (int a = 0; a < in.list.num_triangles; ++a) {
    const double* x[3];  // corners in C, broadcast where used
    const int t = Corners(in.list, a, x);
    const std::array<int, 3>& p = in.list.triangle_p[t];
    const bool full = in.full[a] != 0;
    // Per lane l and corner m, over the chunks: w_m k (ideal - q) per axis and w_m k, as one
    // vector (x, y, z, k); per corner, w over the active samples.
    V4 acc[4][3] = {}, w_sum[3] = {};  // set by the first chunk
    for (int c = 0; c < chunks; ++c) {
      const std::size_t lane0 =
          4 * (static_cast<std::size_t>(t) * static_cast<std::size_t>(chunks) + static_cast<std::size_t>(c));
      const double* wc = layout.w + 12 * c;
      const V4 w[3] = {Load(wc), Load(wc + 4), Load(wc + 8)};
      V4 q[3];
      HAPTEX_UNROLL
      for (int i = 0; i < 3; ++i) q[i] = w[0] * x[0][i] + w[1] * x[1][i] + w[2] * x[2][i];  // broadcasts
      const V4 k = full ? Load(layout.k_full_lanes + 4 * c) : Load(s.k_N_per_m + lane0);
      const M4 active = k > 0.0;
      V4 ix = Load(s.ideal_x_C_m + lane0), iy = Load(s.ideal_y_C_m + lane0);
      const M4 was_sliding = LoadMask(s.sliding + lane0);
      if (loaded) {
        const V4 normal = gps * k;
        const V4 limit = (was_sliding ? Splat(mu_d) : Splat(mu_s)) * normal * (1.0 + 1e-9);
        const V4 sx = q[0] - ix, sy = q[1] - iy;
        const V4 s2 = sx * sx + sy * sy;
        const M4 slide = active & ~(k * k * s2 <= limit * limit);
        if (Any(slide)) {
          const V4 f = mu_d * normal / (k * Sqrt(s2));
          ix = slide ? q[0] - f * sx : ix;
          iy = slide ? q[1] - f * sy : iy;
          Store(ix, s.ideal_x_C_m + lane0);
          Store(iy, s.ideal_y_C_m + lane0);
        }
        StoreMask(active ? slide : was_sliding, s.sliding + lane0);
        sliding_count -= slide;
      } else {
        // No grip, no friction: the ideal position is the frictionless point.
        ix = active ? q[0] : ix;
        iy = active ? q[1] : iy;
        Store(ix, s.ideal_x_C_m + lane0);
        Store(iy, s.ideal_y_C_m + lane0);
        sliding_count -= active & was_sliding;
      }
      k_ideal_x += k * Where(active, ix);
      k_ideal_y += k * Where(active, iy);
      // Lane l's (ideal - q, 1) times each corner's w k of that lane: the products of a
      // lane-wise sum, without its shuffles. (The first chunk is not added to zero: that changes
      // at most the sign of a zero sum, which adding to the particle's sum, never -0, drops.)
      const V4 delta[4] = {Where(active, ix - q[0]), Where(active, iy - q[1]), Where(active, -q[2]), Splat(1.0)};
      V4 lane_delta[4];
      Transpose(delta, lane_delta);
      // w k per [corner][lane], broadcast from memory (full: the layout's products).
      alignas(32) double wk_not_full[12];
      const double* wk = layout.wk_full + 12 * c;
      if (!full) {
        HAPTEX_UNROLL
        for (int m = 0; m < 3; ++m) {
          Store(w[m] * k, wk_not_full + 4 * m);
          w_sum[m] = c == 0 ? Where(active, w[m]) : w_sum[m] + Where(active, w[m]);
        }
        wk = wk_not_full;
      }
      HAPTEX_UNROLL
      for (int l = 0; l < 4; ++l) {
        HAPTEX_UNROLL
        for (int m = 0; m < 3; ++m) {
          const V4 product = wk[4 * m + l] * lane_delta[l];
          acc[l][m] = c == 0 ? product : acc[l][m] + product;
        }
      }
    }
    const V4 w_corner = full ? V4{layout.w_sum_full[0], layout.w_sum_full[1], layout.w_sum_full[2], 0.0}
                             : LaneSums(w_sum[0], w_sum[1], w_sum[2], Splat(0.0));
    HAPTEX_UNROLL
    for (int m = 0; m < 3; ++m) {
      const std::size_t pm = static_cast<std::size_t>(p[static_cast<std::size_t>(m)]);
      double* out = &sums[pm].kd_x_N;
      Store(Load(out) + ((acc[0][m] + acc[1][m]) + (acc[2][m] + acc[3][m])), out);
      w_sums[pm] += w_corner[m];
    }
  }
  const V4 kx_ky = LaneSums(k_ideal_x, k_ideal_y, Splat(0.0), Splat(0.0));
  PinchFrictionTotals totals;
  totals.k_ideal_x_N = kx_ky[0];
  totals.k_ideal_y_N = kx_ky[1];
  totals.sliding = LaneCount(sliding_count);
  return totals;
}

void LocatePortable(const PinchLocateInput& in, const PinchParticleArrays& out) { LocateKernel(in, out); }

PinchClassifyTotals ClassifyPortable(const PinchSampleLayout& layout, const PinchClassifyInput& in,
                                     const PinchSampleArrays& s, PinchTriangleHold* hold) {
  return layout.chunks == 1 ? ClassifyKernel<1>(layout, in, s, hold) : ClassifyKernel<0>(layout, in, s, hold);
}

PinchFrictionTotals FrictionPortable(const PinchSampleLayout& layout, const PinchFrictionInput& in,
                                     const PinchSampleArrays& s, PinchParticleSums* sums, double* w_sums) {
  return layout.chunks == 1 ? FrictionKernel<1>(layout, in, s, sums, w_sums)
                            : FrictionKernel<0>(layout, in, s, sums, w_sums);
}

#ifdef HAPTEX_X86_KERNELS
// The same kernels on 256-bit registers. No FMA: the products round as in the portable build.
__attribute__((target("avx2"))) void LocateAvx2(const PinchLocateInput& in, const PinchParticleArrays& out) {
  LocateKernel(in, out);
}
__attribute__((target("avx2"))) PinchClassifyTotals ClassifyAvx2(const PinchSampleLayout& layout,
                                                                 const PinchClassifyInput& in,
                                                                 const PinchSampleArrays& s, PinchTriangleHold* hold) {
  return layout.chunks == 1 ? ClassifyKernel<1>(layout, in, s, hold) : ClassifyKernel<0>(layout, in, s, hold);
}
__attribute__((target("avx2"))) PinchFrictionTotals FrictionAvx2(const PinchSampleLayout& layout,
                                                                 const PinchFrictionInput& in,
                                                                 const PinchSampleArrays& s, PinchParticleSums* sums,
                                                                 double* w_sums) {
  return layout.chunks == 1 ? FrictionKernel<1>(layout, in, s, sums, w_sums)
                            : FrictionKernel<0>(layout, in, s, sums, w_sums);
}
#endif

}  // namespace

void LocatePinchParticles(const PinchLocateInput& in, const PinchParticleArrays& out, bool avx2) {
#ifdef HAPTEX_X86_KERNELS
  HAPTEX_DEMAND(!avx2 || base::CpuHasAvx2());  // else SIGILL
  if (avx2) return LocateAvx2(in, out);
#else
  HAPTEX_DEMAND(!avx2);
#endif
  LocatePortable(in, out);
}

PinchClassifyTotals ClassifyPinchSamples(const PinchSampleLayout& layout, const PinchClassifyInput& in,
                                         const PinchSampleArrays& samples, PinchTriangleHold* hold, bool avx2) {
#ifdef HAPTEX_X86_KERNELS
  HAPTEX_DEMAND(!avx2 || base::CpuHasAvx2());  // else SIGILL
  if (avx2) return ClassifyAvx2(layout, in, samples, hold);
#else
  HAPTEX_DEMAND(!avx2);
#endif
  return ClassifyPortable(layout, in, samples, hold);
}

PinchFrictionTotals ApplyPinchFriction(const PinchSampleLayout& layout, const PinchFrictionInput& in,
                                       const PinchSampleArrays& samples, PinchParticleSums* sums, double* w_sums,
                                       bool avx2) {
#ifdef HAPTEX_X86_KERNELS
  HAPTEX_DEMAND(!avx2 || base::CpuHasAvx2());  // else SIGILL
  if (avx2) return FrictionAvx2(layout, in, samples, sums, w_sums);
#else
  HAPTEX_DEMAND(!avx2);
#endif
  return FrictionPortable(layout, in, samples, sums, w_sums);
}

}  // namespace haptex::contact::internal
