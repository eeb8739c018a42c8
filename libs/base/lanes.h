#pragma once
// SIMD lanes for the vector kernels of libs/textile and libs/contact (haptex::base::lanes).
// Four doubles as one value (a GCC/Clang vector extension) for kernels built twice: pairs of
// SSE2 operations in the generic build, one AVX operation in a target("avx2") build. Both do the
// same IEEE operations in the same order (no FMA), so their results do not depend on the CPU.
// Every helper is always inlined into its kernel, so it is compiled once per instruction set and
// no 32-byte vector crosses a call in the generic build (where GCC's psabi note would apply).

#include <bit>
#include <cmath>

#ifdef __SSE2__
#include <emmintrin.h>
#endif

// GCC reports the psabi note at the end of the including file, so it stays off from here on.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace haptex::base::lanes {

// Full unrolling of short fixed loops (-O2 keeps them as loops over stack arrays).
#define HAPTEX_UNROLL _Pragma("GCC unroll 9")
#define HAPTEX_LANES_INLINE inline __attribute__((always_inline))
#define HAPTEX_LANES_LAMBDA __attribute__((always_inline))

using V4 = double __attribute__((vector_size(32)));
using M4 = long long __attribute__((vector_size(32)));  // lane masks of V4 comparisons: -1 or 0
using V2 = double __attribute__((vector_size(16)));
constexpr int kLanes = 4;

HAPTEX_LANES_INLINE V4 Splat(double s) { return V4{s, s, s, s}; }
// Four square roots, correctly rounded as std::sqrt: two 2-wide instructions (which the avx2
// build keeps as such) instead of four scalar ones, each with its errno branch.
HAPTEX_LANES_INLINE V4 Sqrt(V4 a) {
#ifdef __SSE2__
  const V2 lo = _mm_sqrt_pd(__builtin_shufflevector(a, a, 0, 1));
  const V2 hi = _mm_sqrt_pd(__builtin_shufflevector(a, a, 2, 3));
  return __builtin_shufflevector(lo, hi, 0, 1, 2, 3);
#else
  return V4{std::sqrt(a[0]), std::sqrt(a[1]), std::sqrt(a[2]), std::sqrt(a[3])};
#endif
}
// |a|: the sign bit cleared, as std::abs does.
HAPTEX_LANES_INLINE V4 Abs(V4 a) { return std::bit_cast<V4>(std::bit_cast<M4>(a) & ~std::bit_cast<M4>(Splat(-0.0))); }
HAPTEX_LANES_INLINE V4 Dot3(const V4* a, const V4* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
// Whether any lane of a mask is set: the two halves or-ed, then one sign-bit mask (SSE2, so in
// both builds) instead of four lane extractions.
HAPTEX_LANES_INLINE bool Any(M4 m) {
#ifdef __SSE2__
  using M2 = long long __attribute__((vector_size(16)));
  const M2 halves = __builtin_shufflevector(m, m, 0, 1) | __builtin_shufflevector(m, m, 2, 3);
  return _mm_movemask_pd(std::bit_cast<__m128d>(halves)) != 0;
#else
  return (m[0] | m[1] | m[2] | m[3]) != 0;
#endif
}
// Lanes of a where the mask is set, 0 elsewhere (bit and: no arithmetic, so a NaN or an
// infinity in a cleared lane does not reach the result).
HAPTEX_LANES_INLINE V4 Where(M4 m, V4 a) { return std::bit_cast<V4>(m & std::bit_cast<M4>(a)); }
// 4x4 transpose: rows r[e] (entry e of lanes 0..3) become c[j] (entries 0..3 of lane j).
HAPTEX_LANES_INLINE void Transpose(const V4 r[4], V4 c[4]) {
  const V4 t0 = __builtin_shufflevector(r[0], r[1], 0, 4, 2, 6);
  const V4 t1 = __builtin_shufflevector(r[0], r[1], 1, 5, 3, 7);
  const V4 t2 = __builtin_shufflevector(r[2], r[3], 0, 4, 2, 6);
  const V4 t3 = __builtin_shufflevector(r[2], r[3], 1, 5, 3, 7);
  c[0] = __builtin_shufflevector(t0, t2, 0, 1, 4, 5);
  c[1] = __builtin_shufflevector(t1, t3, 0, 1, 4, 5);
  c[2] = __builtin_shufflevector(t0, t2, 2, 3, 6, 7);
  c[3] = __builtin_shufflevector(t1, t3, 2, 3, 6, 7);
}
// The sums of the lanes of a, b, c and d, in that order: (a0 + a1) + (a2 + a3) and so on.
HAPTEX_LANES_INLINE V4 LaneSums(V4 a, V4 b, V4 c, V4 d) {
  const V4 ab = __builtin_shufflevector(a, b, 0, 4, 2, 6) + __builtin_shufflevector(a, b, 1, 5, 3, 7);
  const V4 cd = __builtin_shufflevector(c, d, 0, 4, 2, 6) + __builtin_shufflevector(c, d, 1, 5, 3, 7);
  return __builtin_shufflevector(ab, cd, 0, 1, 4, 5) + __builtin_shufflevector(ab, cd, 2, 3, 6, 7);
}

}  // namespace haptex::base::lanes
