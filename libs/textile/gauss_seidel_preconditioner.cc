#include "libs/textile/gauss_seidel_preconditioner.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "libs/base/cpu_features.h"
#include "libs/base/demand.h"

#ifdef HAPTEX_X86_KERNELS
#include <immintrin.h>
#endif

namespace haptex::textile {
namespace {

using internal::GaussSeidelSweepArgs;
using internal::PaddedBlock;

enum class SweepKind {
  kForward,  // y = (D_w + L)^-1 x
  // kForward, then z = D_w y row by row and the sum of y . z (as MultiplyDiagonal).
  kForwardDiagonal,
  kBackward,  // y = (D_w + U)^-1 x
  // Eisenstat's backward half: t = (D_w + U)^-1 x, and z = x - (2 - omega) D_w t in the same
  // pass (0 in rows that are not free, where x and D_w are 0).
  kEisenstatBackward,
  // kEisenstatBackward after x = s + beta x, row by row (the sweep reads x only in row r).
  kEisenstatBackwardUpdate,
  // Eisenstat's forward half: w = (D_w + L)^-1 z, kept in z (row r's z is dead once read),
  // y = w + t, and the sum of x . y.
  kEisenstatForward,
};

constexpr bool IsForward(SweepKind k) {
  return k == SweepKind::kForward || k == SweepKind::kForwardDiagonal || k == SweepKind::kEisenstatForward;
}
constexpr bool IsEisenstatBackward(SweepKind k) {
  return k == SweepKind::kEisenstatBackward || k == SweepKind::kEisenstatBackwardUpdate;
}

// A sweep's vectors (rows 4 apart); x is written only by kEisenstatBackwardUpdate.
struct SweepVectors {
  const double* x;
  double* y;
  double* t;
  double* z;
  const double* s;             // kEisenstatBackwardUpdate's
  double beta;                 // likewise
  double* x_update = nullptr;  // likewise: x itself, updated in place to s + beta x
};

// The vector a sweep solves into, whose earlier rows its sums read: y, t, or w kept in z.
template <SweepKind kKind>
inline double* Solved(const SweepVectors& v) {
  return kKind == SweepKind::kEisenstatForward ? v.z : IsEisenstatBackward(kKind) ? v.t : v.y;
}

// Zeroes rows [r0, r1) of a padded vector, pads too.
inline void ZeroRows(double* v, int r0, int r1) {
  for (int r = r0; r < r1; ++r) {
    double* row = v + 4 * r;
    row[0] = row[1] = row[2] = row[3] = 0.0;
  }
}

// A sweep skips the rows that are not free (rows [r0, r1) here) and zeroes what it writes
// there instead. kEisenstatForward's w (kept in z) was zeroed there by the backward half just
// before it, and kEisenstatBackwardUpdate's x is 0 there already (inputs must be).
template <SweepKind kKind>
inline void ZeroSkipped(const SweepVectors& v, int r0, int r1) {
  if (kKind != SweepKind::kEisenstatForward) ZeroRows(Solved<kKind>(v), r0, r1);
  if (kKind == SweepKind::kForwardDiagonal || IsEisenstatBackward(kKind)) ZeroRows(v.z, r0, r1);
  if (kKind == SweepKind::kEisenstatForward) ZeroRows(v.y, r0, r1);
}

// Runs `row(r)` for the free rows in the sweep's order (forward: ascending), with
// `skipped(r0, r1)` for each range of other rows in between.
template <bool kForward, typename Row, typename Skipped>
inline __attribute__((always_inline)) void ForEachFreeRow(const GaussSeidelSweepArgs& a, Row row, Skipped skipped) {
  if constexpr (kForward) {
    int done = 0;
    for (int i = 0; i < a.num_runs; ++i) {
      const int r0 = a.runs[2 * i], r1 = a.runs[2 * i + 1];
      skipped(done, r0);
      for (int r = r0; r < r1; ++r) row(r);
      done = r1;
    }
    skipped(done, a.rows);
  } else {
    int done = a.rows;
    for (int i = a.num_runs - 1; i >= 0; --i) {
      const int r0 = a.runs[2 * i], r1 = a.runs[2 * i + 1];
      skipped(r1, done);
      for (int r = r1 - 1; r >= r0; --r) row(r);
      done = r0;
    }
    skipped(0, done);
  }
}

// y = D x for one row (its pad left as it is), returning x . y as (x_0 y_0 + x_1 y_1) + x_2 y_2.
inline double DiagonalRowGeneric(const PaddedBlock& d, const double* x, double* y) {
  for (int i = 0; i < 3; ++i) y[i] = (d.col[0][i] * x[0] + d.col[1][i] * x[1]) + d.col[2][i] * x[2];
  return (x[0] * y[0] + x[1] * y[1]) + x[2] * y[2];
}

// A row's column offsets (SweepRow), its first general block's entries (column-major, the
// others follow 9 apart) and its first scalar block's value.
inline const int* Columns(const GaussSeidelSweepArgs& a, const internal::SweepRow& q) {
  return q.common != 0 ? q.column : a.column_offset + q.column[0];
}
inline const double* FirstBlock(const GaussSeidelSweepArgs& a, const internal::SweepRow& q) {
  return reinterpret_cast<const double*>(reinterpret_cast<const char*>(a.blocks) + q.block_bytes);
}
inline const double* FirstScalar(const GaussSeidelSweepArgs& a, const internal::SweepRow& q) {
  return reinterpret_cast<const double*>(reinterpret_cast<const char*>(a.scalars) + q.scalar_bytes);
}

// Rows are 4 apart (padded_vector.h). One row of a sweep, portable. Per component i, in this
// order (the AVX2 row does the same operations, lane i for component i, so both give identical
// results):
//   c_j = sum over the general blocks of m(i, j) y_j (j = 0, 1, 2, each its own sum)
//   acc = x - ((c_0 + c_1) + c_2) - sum over the scalar blocks of v y
//   o   = ((Dinv(i,0) acc_0 + Dinv(i,1) acc_1) + Dinv(i,2) acc_2)
//         - ((G(i,0) p_0 + G(i,1) p_1) + G(i,2) p_2)      (p: the row solved just before)
// and in the Eisenstat forward half the row's x . y as (x_0 y_0 + x_1 y_1) + x_2 y_2.
template <SweepKind kKind>
inline double RowGeneric(const GaussSeidelSweepArgs& a, int r, const SweepVectors& v) {
  constexpr bool kForward = IsForward(kKind);
  double* solved = Solved<kKind>(v);
  const double* x = v.x;
  if constexpr (kKind == SweepKind::kEisenstatBackwardUpdate) {
    for (int i = 0; i < 4; ++i) v.x_update[4 * r + i] = v.s[4 * r + i] + v.beta * v.x_update[4 * r + i];
  }
  const double* in = kKind == SweepKind::kEisenstatForward ? v.z : x;
  const internal::SweepRowData& row = a.row[r];
  const internal::SweepRow& q = row.shape[kForward ? 0 : 1];
  double c[3][3] = {};
  const int* offset = Columns(a, q);
  const double* blocks = FirstBlock(a, q);
  for (int k = 0; k < q.general; ++k) {
    const double* m = blocks + 9 * k;
    const double* yc = solved + offset[k];
    for (int j = 0; j < 3; ++j) {
      for (int i = 0; i < 3; ++i) c[j][i] += m[3 * j + i] * yc[j];
    }
  }
  double sc[3] = {};
  for (int k = 0; k < q.scalars; ++k) {
    const double* yc = solved + offset[q.general + k];
    for (int i = 0; i < 3; ++i) sc[i] += FirstScalar(a, q)[k] * yc[i];
  }
  double acc[3];
  for (int i = 0; i < 3; ++i) acc[i] = (in[4 * r + i] - ((c[0][i] + c[1][i]) + c[2][i])) - sc[i];
  const PaddedBlock& inv = row.diag_inv;
  double o[3];
  for (int i = 0; i < 3; ++i) {
    o[i] = (inv.col[0][i] * acc[0] + inv.col[1][i] * acc[1]) + inv.col[2][i] * acc[2];
  }
  if (q.adjacent) {
    const double* p = solved + 4 * (kForward ? r - 1 : r + 1);
    const PaddedBlock& g = row.adjacent_scaled[kForward ? 0 : 1];
    for (int i = 0; i < 3; ++i) o[i] -= (g.col[0][i] * p[0] + g.col[1][i] * p[1]) + g.col[2][i] * p[2];
  }
  for (int i = 0; i < 3; ++i) solved[4 * r + i] = o[i];
  if constexpr (IsEisenstatBackward(kKind)) {
    const PaddedBlock& d = row.diag;
    for (int i = 0; i < 3; ++i) {
      v.z[4 * r + i] = x[4 * r + i] - a.diag_excess * ((d.col[0][i] * o[0] + d.col[1][i] * o[1]) + d.col[2][i] * o[2]);
    }
  } else if constexpr (kKind == SweepKind::kForwardDiagonal) {
    return DiagonalRowGeneric(row.diag, o, v.z + 4 * r);
  } else if constexpr (kKind == SweepKind::kEisenstatForward) {
    double yr[3];
    for (int i = 0; i < 3; ++i) {
      yr[i] = o[i] + v.t[4 * r + i];
      v.y[4 * r + i] = yr[i];
    }
    return (x[4 * r] * yr[0] + x[4 * r + 1] * yr[1]) + x[4 * r + 2] * yr[2];
  }
  return 0.0;
}

#ifdef HAPTEX_X86_KERNELS
// The broadcasts of lanes 0, 1, 2 of a row's solution: a row's products with its solution (D_w
// times it) and the next row's (the adjacent block times it) share them (port 5 shuffles).
struct Broadcasts {
  __m256d b0, b1, b2;
};

__attribute__((target("avx2"), always_inline)) inline Broadcasts BroadcastAvx2(__m256d x) {
  return {_mm256_permute4x64_pd(x, 0x00), _mm256_permute4x64_pd(x, 0x55), _mm256_permute4x64_pd(x, 0xAA)};
}

// (b(:, 0) x_0 + b(:, 1) x_1) + b(:, 2) x_2, x as its broadcasts.
__attribute__((target("avx2"), always_inline)) inline __m256d ProductAvx2(const PaddedBlock& b, const Broadcasts& x) {
  return _mm256_add_pd(
      _mm256_add_pd(_mm256_mul_pd(_mm256_load_pd(b.col[0]), x.b0), _mm256_mul_pd(_mm256_load_pd(b.col[1]), x.b1)),
      _mm256_mul_pd(_mm256_load_pd(b.col[2]), x.b2));
}

// y = D x for one row (lane 3 too: 0 for a finite x), returning x . y as (x_0 y_0 + x_1 y_1) + x_2 y_2;
// xb: x's broadcasts.
__attribute__((target("avx2"), always_inline)) inline double DiagonalRowAvx2(const PaddedBlock& d, __m256d x,
                                                                             const Broadcasts& xb, double* y) {
  const __m256d yr = ProductAvx2(d, xb);
  _mm256_store_pd(y, yr);
  const __m256d p = _mm256_mul_pd(x, yr);
  const __m128d p01 = _mm256_castpd256_pd128(p);
  const __m128d sum01 = _mm_add_sd(p01, _mm_unpackhi_pd(p01, p01));
  return _mm_cvtsd_f64(_mm_add_sd(sum01, _mm256_extractf128_pd(p, 1)));
}

__attribute__((target("avx2"), always_inline)) inline double DiagonalRowAvx2(const PaddedBlock& d, __m256d x,
                                                                             double* y) {
  return DiagonalRowAvx2(d, x, BroadcastAvx2(x), y);
}

// For each of kSystems systems: c_j += column j of block m times y_j, j = 0, 1, 2 (lane 3: see
// RowAvx2); m loaded once for all. Column 2 is a masked load (extra uops) only where no block
// may follow m in memory (kLast): elsewhere its lane 3 is the next block's entry 0.
template <int kSystems, bool kLast>
__attribute__((target("avx2"), always_inline)) inline void GeneralBlockAvx2(const double* m, const double* const* y,
                                                                            int offset, __m256d (*c)[3]) {
  const __m256d m0 = _mm256_loadu_pd(m), m1 = _mm256_loadu_pd(m + 3),
                m2 = kLast ? _mm256_maskload_pd(m + 6, _mm256_set_epi64x(0, -1, -1, -1)) : _mm256_loadu_pd(m + 6);
#pragma GCC unroll 2
  for (int i = 0; i < kSystems; ++i) {
    const double* yc = y[i] + offset;
    c[i][0] = _mm256_add_pd(c[i][0], _mm256_mul_pd(m0, _mm256_broadcast_sd(yc)));
    c[i][1] = _mm256_add_pd(c[i][1], _mm256_mul_pd(m1, _mm256_broadcast_sd(yc + 1)));
    c[i][2] = _mm256_add_pd(c[i][2], _mm256_mul_pd(m2, _mm256_broadcast_sd(yc + 2)));
  }
}

// For each of kSystems systems: sc += value times y's row at offset.
template <int kSystems>
__attribute__((target("avx2"), always_inline)) inline void ScalarBlockAvx2(const double* value, const double* const* y,
                                                                           int offset, __m256d* sc) {
  const __m256d v = _mm256_broadcast_sd(value);
#pragma GCC unroll 2
  for (int i = 0; i < kSystems; ++i) sc[i] = _mm256_add_pd(sc[i], _mm256_mul_pd(v, _mm256_load_pd(y[i] + offset)));
}

// Per system a row's sums (from 0, in order): c[j] of its general blocks (m: the first, 9 doubles
// apart), sc of its scalar blocks (value: the first). kCommon: the row's SweepRow::common, its
// counts fixed (no loop, no test, no masked load); 0: the counts and offsets of q.
template <int kSystems, int kCommon>
__attribute__((target("avx2"), always_inline)) inline void RowSumsAvx2(const GaussSeidelSweepArgs& a,
                                                                       const internal::SweepRow& q,
                                                                       const double* const* y, __m256d (*c)[3],
                                                                       __m256d* sc) {
  const double* m = FirstBlock(a, q);
  const double* value = FirstScalar(a, q);
#pragma GCC unroll 2
  for (int i = 0; i < kSystems; ++i) sc[i] = c[i][0] = c[i][1] = c[i][2] = _mm256_setzero_pd();
  if constexpr (kCommon != 0) {
    GeneralBlockAvx2<kSystems, false>(m, y, q.column[0], c);
    if constexpr (kCommon == 3) {
      GeneralBlockAvx2<kSystems, false>(m + 9, y, q.column[1], c);
      GeneralBlockAvx2<kSystems, false>(m + 18, y, q.column[2], c);
    }
    ScalarBlockAvx2<kSystems>(value, y, q.column[kCommon], sc);
    ScalarBlockAvx2<kSystems>(value + 1, y, q.column[kCommon + 1], sc);
  } else {
    const int* offset = a.column_offset + q.column[0];
    const int general = q.general, scalars = q.scalars;
    if (general > 0) {
      for (int k = 0; k < general - 1; ++k) GeneralBlockAvx2<kSystems, false>(m + 9 * k, y, offset[k], c);
      GeneralBlockAvx2<kSystems, true>(m + 9 * (general - 1), y, offset[general - 1], c);
    }
    for (int k = 0; k < scalars; ++k) ScalarBlockAvx2<kSystems>(value + k, y, offset[general + k], sc);
  }
}

// The row in 4-wide registers: lanes 0..2 are components 0..2. Lane 3 of the sums holds
// garbage (a general block's column loads reach into its next column), which only lane 3 of
// D_w^-1 (zero) multiplies: the row's pad is stored as 0. No FMA (target avx2 only): products
// round as in RowGeneric. `prev`: the broadcasts of the row solved just before, kept in
// registers; set to this row's. kCommon: as RowSumsAvx2's (common rows have an adjacent block).
template <SweepKind kKind, int kCommon>
__attribute__((target("avx2"), always_inline)) inline void RowAvx2(const GaussSeidelSweepArgs& a,
                                                                   const internal::SweepRowData& row, int i,
                                                                   const SweepVectors& v, Broadcasts* prev,
                                                                   double* xy) {
  constexpr int kDirection = IsForward(kKind) ? 0 : 1;
  double* solved = Solved<kKind>(v);
  const internal::SweepRow& q = row.shape[kDirection];
  // x's update first: GCC then keeps each sum's loads next to their products (a store between
  // them held all of a common row's loaded columns in registers, spilling).
  __m256d in;
  if constexpr (kKind == SweepKind::kEisenstatBackwardUpdate) {
    in = _mm256_add_pd(_mm256_load_pd(v.s + i), _mm256_mul_pd(_mm256_set1_pd(v.beta), _mm256_load_pd(v.x_update + i)));
    _mm256_store_pd(v.x_update + i, in);
  } else {
    in = _mm256_load_pd((kKind == SweepKind::kEisenstatForward ? v.z : v.x) + i);
  }
  __m256d c[1][3], sum[1];
  const double* const y[1] = {solved};
  RowSumsAvx2<1, kCommon>(a, q, y, c, sum);
  const __m256d c0 = c[0][0], c1 = c[0][1], c2 = c[0][2], sc = sum[0];
  const __m256d acc = _mm256_sub_pd(_mm256_sub_pd(in, _mm256_add_pd(_mm256_add_pd(c0, c1), c2)), sc);
  __m256d o = ProductAvx2(row.diag_inv, BroadcastAvx2(acc));
  if (kCommon != 0 || q.adjacent) o = _mm256_sub_pd(o, ProductAvx2(row.adjacent_scaled[kDirection], *prev));
  _mm256_store_pd(solved + i, o);
  const Broadcasts ob = BroadcastAvx2(o);
  if constexpr (IsEisenstatBackward(kKind)) {
    const __m256d dt = ProductAvx2(row.diag, ob);
    _mm256_store_pd(v.z + i, _mm256_sub_pd(in, _mm256_mul_pd(_mm256_set1_pd(a.diag_excess), dt)));
  } else if constexpr (kKind == SweepKind::kForwardDiagonal) {
    *xy += DiagonalRowAvx2(row.diag, o, ob, v.z + i);
  } else if constexpr (kKind == SweepKind::kEisenstatForward) {
    const __m256d yr = _mm256_add_pd(o, _mm256_load_pd(v.t + i));
    _mm256_store_pd(v.y + i, yr);
    alignas(32) double p[4];
    _mm256_store_pd(p, _mm256_mul_pd(_mm256_load_pd(v.x + i), yr));
    *xy += (p[0] + p[1]) + p[2];
  }
  *prev = ob;
}

// RowAvx2 for row r's shape (common rows alternate 3 and 1 general blocks on a grid: predicted).
template <SweepKind kKind>
__attribute__((target("avx2"), always_inline)) inline void AnyRowAvx2(const GaussSeidelSweepArgs& a,
                                                                      const internal::SweepRowData& row, int i,
                                                                      const SweepVectors& v, Broadcasts* prev,
                                                                      double* xy) {
  const int common = row.shape[IsForward(kKind) ? 0 : 1].common;
  if (common == 3) {
    RowAvx2<kKind, 3>(a, row, i, v, prev, xy);
  } else if (common == 1) {
    RowAvx2<kKind, 1>(a, row, i, v, prev, xy);
  } else {
    RowAvx2<kKind, 0>(a, row, i, v, prev, xy);
  }
}

// `a` by value: a local copy, kept in registers (the stores of __m256d may alias anything).
template <SweepKind kKind>
__attribute__((target("avx2"))) double SweepAvx2(GaussSeidelSweepArgs a, SweepVectors v) {
  // ForEachFreeRow's order, written out (a lambda would not be built for AVX2). A run starts
  // with prev = 0: the row before it is not free, so its adjacent block is 0.
  double xy = 0.0;
  const __m256d zero = _mm256_setzero_pd();
  if constexpr (IsForward(kKind)) {
    int done = 0;
    for (int i = 0; i < a.num_runs; ++i) {
      const int r0 = a.runs[2 * i], r1 = a.runs[2 * i + 1];
      ZeroSkipped<kKind>(v, done, r0);
      Broadcasts prev = {zero, zero, zero};
      const internal::SweepRowData* row = a.row + r0;
      for (int k = 4 * r0; k < 4 * r1; k += 4, ++row) AnyRowAvx2<kKind>(a, *row, k, v, &prev, &xy);
      done = r1;
    }
    ZeroSkipped<kKind>(v, done, a.rows);
  } else {
    int done = a.rows;
    for (int i = a.num_runs - 1; i >= 0; --i) {
      const int r0 = a.runs[2 * i], r1 = a.runs[2 * i + 1];
      ZeroSkipped<kKind>(v, r1, done);
      Broadcasts prev = {zero, zero, zero};
      const internal::SweepRowData* row = a.row + r1;
      for (int k = 4 * r1 - 4; k >= 4 * r0; k -= 4) AnyRowAvx2<kKind>(a, *--row, k, v, &prev, &xy);
      done = r0;
    }
    ZeroSkipped<kKind>(v, 0, done);
  }
  return xy;
}

// One row of two kForwardDiagonal sweeps (v0, v1): each block, D_w^-1, the adjacent block and
// D_w loaded once for both; per system the operations of RowAvx2<kForwardDiagonal> in its
// order, so the bits of two separate sweeps. prev0, prev1: as RowAvx2's prev, updated.
template <int kCommon>
__attribute__((target("avx2"), always_inline)) inline void PairRowAvx2(const GaussSeidelSweepArgs& a, int r,
                                                                       const SweepVectors& v0, const SweepVectors& v1,
                                                                       Broadcasts* prev0, Broadcasts* prev1,
                                                                       double* xy0, double* xy1) {
  const internal::SweepRowData& row = a.row[r];
  const internal::SweepRow& q = row.shape[0];
  __m256d c[2][3], sum[2];
  const double* const y[2] = {v0.y, v1.y};
  RowSumsAvx2<2, kCommon>(a, q, y, c, sum);
  const __m256d c0 = c[0][0], c1 = c[0][1], c2 = c[0][2], sc = sum[0];
  const __m256d e0 = c[1][0], e1 = c[1][1], e2 = c[1][2], se = sum[1];
  const __m256d acc0 =
      _mm256_sub_pd(_mm256_sub_pd(_mm256_load_pd(v0.x + 4 * r), _mm256_add_pd(_mm256_add_pd(c0, c1), c2)), sc);
  const __m256d acc1 =
      _mm256_sub_pd(_mm256_sub_pd(_mm256_load_pd(v1.x + 4 * r), _mm256_add_pd(_mm256_add_pd(e0, e1), e2)), se);
  __m256d o0 = ProductAvx2(row.diag_inv, BroadcastAvx2(acc0));
  __m256d o1 = ProductAvx2(row.diag_inv, BroadcastAvx2(acc1));
  if (kCommon != 0 || q.adjacent) {
    o0 = _mm256_sub_pd(o0, ProductAvx2(row.adjacent_scaled[0], *prev0));
    o1 = _mm256_sub_pd(o1, ProductAvx2(row.adjacent_scaled[0], *prev1));
  }
  _mm256_store_pd(v0.y + 4 * r, o0);
  _mm256_store_pd(v1.y + 4 * r, o1);
  *prev0 = BroadcastAvx2(o0);
  *prev1 = BroadcastAvx2(o1);
  *xy0 += DiagonalRowAvx2(row.diag, o0, *prev0, v0.z + 4 * r);
  *xy1 += DiagonalRowAvx2(row.diag, o1, *prev1, v1.z + 4 * r);
}

// Two kForwardDiagonal sweeps in one pass (PairRowAvx2), in ForEachFreeRow's order written out.
__attribute__((target("avx2"))) void SweepForwardDiagonalPairAvx2(GaussSeidelSweepArgs a, SweepVectors v0,
                                                                  SweepVectors v1, double* xy) {
  double xy0 = 0.0, xy1 = 0.0;
  int done = 0;
  const __m256d zero = _mm256_setzero_pd();
  for (int i = 0; i < a.num_runs; ++i) {
    const int r0 = a.runs[2 * i], r1 = a.runs[2 * i + 1];
    ZeroSkipped<SweepKind::kForwardDiagonal>(v0, done, r0);
    ZeroSkipped<SweepKind::kForwardDiagonal>(v1, done, r0);
    Broadcasts prev0 = {zero, zero, zero}, prev1 = prev0;
    for (int r = r0; r < r1; ++r) {
      const int common = a.row[r].shape[0].common;
      if (common == 3) {
        PairRowAvx2<3>(a, r, v0, v1, &prev0, &prev1, &xy0, &xy1);
      } else if (common == 1) {
        PairRowAvx2<1>(a, r, v0, v1, &prev0, &prev1, &xy0, &xy1);
      } else {
        PairRowAvx2<0>(a, r, v0, v1, &prev0, &prev1, &xy0, &xy1);
      }
    }
    done = r1;
  }
  ZeroSkipped<SweepKind::kForwardDiagonal>(v0, done, a.rows);
  ZeroSkipped<SweepKind::kForwardDiagonal>(v1, done, a.rows);
  xy[0] = xy0;
  xy[1] = xy1;
}

// y = D_w x per row and the sum of the rows' x . y.
__attribute__((target("avx2"))) double MultiplyDiagonalAvx2(const internal::SweepRowData* row, int rows,
                                                            const double* x, double* y) {
  double xy = 0.0;
  for (int r = 0; r < rows; ++r) xy += DiagonalRowAvx2(row[r].diag, _mm256_load_pd(x + 4 * r), y + 4 * r);
  return xy;
}

// CG's step (StepResidual) over the rows of runs [runs[2i], runs[2i + 1]), ascending; with
// kYZero y = 0 in the rows between. The row record is walked by pointer (no index arithmetic
// per row).
template <bool kYZero>
__attribute__((target("avx2"))) double StepResidualAvx2(const internal::SweepRowData* row, const int* runs,
                                                        int num_runs, int rows, double alpha, const double* t,
                                                        const double* q, double* y, double* r, double* s) {
  const __m256d a = _mm256_set1_pd(alpha);
  double xy = 0.0;
  int done = 0;
  for (int run = 0; run < num_runs; ++run) {
    const int r0 = runs[2 * run], r1 = runs[2 * run + 1];
    if constexpr (kYZero) ZeroRows(y, done, r0);
    const internal::SweepRowData* d = row + r0;
    for (int i = 4 * r0; i < 4 * r1; i += 4, ++d) {
      const __m256d y0 = kYZero ? _mm256_setzero_pd() : _mm256_load_pd(y + i);
      _mm256_store_pd(y + i, _mm256_add_pd(y0, _mm256_mul_pd(a, _mm256_load_pd(t + i))));
      const __m256d ri = _mm256_sub_pd(_mm256_load_pd(r + i), _mm256_mul_pd(a, _mm256_load_pd(q + i)));
      _mm256_store_pd(r + i, ri);
      xy += DiagonalRowAvx2(d->diag, ri, s + i);
    }
    done = r1;
  }
  if constexpr (kYZero) ZeroRows(y, done, rows);
  return xy;
}
#endif

template <SweepKind kKind>
double Sweep(const GaussSeidelSweepArgs& a, const SweepVectors& v) {
#ifdef HAPTEX_X86_KERNELS
  if (a.avx2) return SweepAvx2<kKind>(a, v);
#endif
  double xy = 0.0;
  ForEachFreeRow<IsForward(kKind)>(
      a, [&](int r) { xy += RowGeneric<kKind>(a, r, v); }, [&](int r0, int r1) { ZeroSkipped<kKind>(v, r0, r1); });
  return xy;
}

// Two kForwardDiagonal sweeps in one pass over the rows (independent: the bits of two sweeps).
void SweepForwardDiagonalPair(const GaussSeidelSweepArgs& a, const SweepVectors& v0, const SweepVectors& v1,
                              double* xy) {
#ifdef HAPTEX_X86_KERNELS
  if (a.avx2) return SweepForwardDiagonalPairAvx2(a, v0, v1, xy);
#endif
  double xy0 = 0.0, xy1 = 0.0;
  ForEachFreeRow<true>(
      a,
      [&](int r) {
        xy0 += RowGeneric<SweepKind::kForwardDiagonal>(a, r, v0);
        xy1 += RowGeneric<SweepKind::kForwardDiagonal>(a, r, v1);
      },
      [&](int r0, int r1) {
        ZeroSkipped<SweepKind::kForwardDiagonal>(v0, r0, r1);
        ZeroSkipped<SweepKind::kForwardDiagonal>(v1, r0, r1);
      });
  xy[0] = xy0;
  xy[1] = xy1;
}

// A row's blocks (SetRowBlocks) on GCC vector extensions: the generic build does each 4-wide
// operation as SSE2 pairs, the avx2 build as one instruction; the same IEEE operations in the
// same order, so identical results.
#pragma GCC diagnostic ignored "-Wpsabi"  // 32-byte vectors only inside always-inlined code
using V4 = double __attribute__((vector_size(32)));

inline __attribute__((always_inline)) V4 LoadColumn(const PaddedBlock& b, int j) {
  V4 v;
  std::memcpy(&v, b.col[j], sizeof v);
  return v;
}
inline __attribute__((always_inline)) void StoreColumn(V4 v, PaddedBlock* b, int j) {
  std::memcpy(b->col[j], &v, sizeof v);
}

// u x v of lanes 0..2 (lane 3: 0) from scalar products. Vectors are built from scalars, not
// copied in with a 3-double memcpy: that went through the stack and stalled its 4-wide reload
// (BM_GaussSeidelUpdate took about twice as long).
inline __attribute__((always_inline)) V4 Cross(V4 u, V4 v) {
  return V4{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0], 0.0};
}

// out = d_inv m (lane 3 of each column: 0, from d_inv's).
inline __attribute__((always_inline)) void Premultiply(const PaddedBlock& d_inv, const Eigen::Matrix3d& m,
                                                       PaddedBlock* out) {
  const V4 c0 = LoadColumn(d_inv, 0), c1 = LoadColumn(d_inv, 1), c2 = LoadColumn(d_inv, 2);
#pragma GCC unroll 3
  for (int j = 0; j < 3; ++j) StoreColumn((c0 * m(0, j) + c1 * m(1, j)) + c2 * m(2, j), out, j);
}

inline __attribute__((always_inline)) bool RowBlocksKernel(const Eigen::Matrix3d& a, double omega, double inv_omega,
                                                           const Eigen::Matrix3d* lower_block,
                                                           const Eigen::Matrix3d* upper_block, PaddedBlock* d,
                                                           PaddedBlock* d_inv, PaddedBlock* lower, PaddedBlock* upper) {
  // D_w = a / omega (inv_omega = 1 / omega) and D_w^-1 = omega adj(a) / det(a): the adjugate's
  // columns are cross products of a's rows.
  const V4 r0 = {a(0, 0), a(0, 1), a(0, 2), 0.0}, r1 = {a(1, 0), a(1, 1), a(1, 2), 0.0},
           r2 = {a(2, 0), a(2, 1), a(2, 2), 0.0};
  // (r1 x r2) . r0 = det, (r1 x r2) . r1 = 0.
  const V4 adj0 = Cross(r1, r2), adj1 = Cross(r2, r0), adj2 = Cross(r0, r1);
  const double det = (r0[0] * adj0[0] + r0[1] * adj0[1]) + r0[2] * adj0[2];
  const double s = omega / det;
  const V4 col0 = adj0 * s, col1 = adj1 * s, col2 = adj2 * s;  // columns of D_w^-1
  // An infinite or NaN entry makes the sum of all nine non-finite.
  const V4 sum = (col0 + col1) + col2;
  if (!(det != 0.0) || !std::isfinite(s) || !std::isfinite((sum[0] + sum[1]) + sum[2])) return false;
  for (int j = 0; j < 3; ++j) StoreColumn(V4{a(0, j), a(1, j), a(2, j), 0.0} * inv_omega, d, j);
  StoreColumn(col0, d_inv, 0);
  StoreColumn(col1, d_inv, 1);
  StoreColumn(col2, d_inv, 2);
  if (lower_block != nullptr) Premultiply(*d_inv, *lower_block, lower);
  if (upper_block != nullptr) Premultiply(*d_inv, *upper_block, upper);
  return true;
}

// What UpdateRows reads and writes.
struct RowUpdate {
  const int* diag_slot;
  const unsigned char* free;
  const Eigen::Matrix3d* blocks;
  double omega;
  double inv_omega;  // 1 / omega
  int rows;
  internal::SweepRowData* row;
  unsigned char* zero;  // per row: its four blocks are all 0 (kept by the kernel)
};

// Each row's blocks (RowBlocksKernel) where the row is free, zeros elsewhere; the adjacent
// blocks only where the neighbour is free too. Returns false if a free row's failed (its blocks
// zeroed). A row that is not free is zeroed only if it is not all 0 already (the rows fixed
// tick after tick cost one test).
inline __attribute__((always_inline)) bool RowUpdatesKernel(const RowUpdate& in) {
  const RowUpdate u = in;  // a local copy, kept in registers (the stores may alias `in`)
  bool ok = true;
  for (int r = 0; r < u.rows; ++r) {
    internal::SweepRowData& d = u.row[r];
    if (u.free[r] == 0) {
      if (u.zero[r] == 0) {
        d.diag.SetZero();
        d.diag_inv.SetZero();
        d.adjacent_scaled[0].SetZero();
        d.adjacent_scaled[1].SetZero();
        u.zero[r] = 1;
      }
      continue;
    }
    const bool lower = d.shape[0].adjacent && u.free[r - 1];
    const bool upper = d.shape[1].adjacent && u.free[r + 1];
    if (!lower) d.adjacent_scaled[0].SetZero();
    if (!upper) d.adjacent_scaled[1].SetZero();
    // The row's neighbours r -+ 1 are next to its diagonal.
    const Eigen::Matrix3d* a = u.blocks + u.diag_slot[r];
    const bool row_ok = RowBlocksKernel(*a, u.omega, u.inv_omega, lower ? a - 1 : nullptr, upper ? a + 1 : nullptr,
                                        &d.diag, &d.diag_inv, &d.adjacent_scaled[0], &d.adjacent_scaled[1]);
    u.zero[r] = row_ok ? 0 : 1;
    if (!row_ok) {
      d.diag.SetZero();
      d.diag_inv.SetZero();
      d.adjacent_scaled[0].SetZero();
      d.adjacent_scaled[1].SetZero();
      ok = false;
    }
  }
  return ok;
}

bool RowUpdatesGeneric(const RowUpdate& u) { return RowUpdatesKernel(u); }

#ifdef HAPTEX_X86_KERNELS
__attribute__((target("avx2"))) bool RowUpdatesAvx2(const RowUpdate& u) { return RowUpdatesKernel(u); }
#endif

bool RowBlocksGeneric(const Eigen::Matrix3d& a, double omega, const Eigen::Matrix3d* lower_block,
                      const Eigen::Matrix3d* upper_block, PaddedBlock* d, PaddedBlock* d_inv, PaddedBlock* lower,
                      PaddedBlock* upper) {
  return RowBlocksKernel(a, omega, 1.0 / omega, lower_block, upper_block, d, d_inv, lower, upper);
}

#ifdef HAPTEX_X86_KERNELS
__attribute__((target("avx2"))) bool RowBlocksAvx2(const Eigen::Matrix3d& a, double omega,
                                                   const Eigen::Matrix3d* lower_block,
                                                   const Eigen::Matrix3d* upper_block, PaddedBlock* d,
                                                   PaddedBlock* d_inv, PaddedBlock* lower, PaddedBlock* upper) {
  return RowBlocksKernel(a, omega, 1.0 / omega, lower_block, upper_block, d, d_inv, lower, upper);
}
#endif

}  // namespace

namespace internal {
bool SetRowBlocks(const Eigen::Matrix3d& a, double omega, const Eigen::Matrix3d* lower_block,
                  const Eigen::Matrix3d* upper_block, bool avx2, PaddedBlock* d, PaddedBlock* d_inv, PaddedBlock* lower,
                  PaddedBlock* upper) {
#ifdef HAPTEX_X86_KERNELS
  if (avx2) return RowBlocksAvx2(a, omega, lower_block, upper_block, d, d_inv, lower, upper);
#endif
  (void)avx2;
  return RowBlocksGeneric(a, omega, lower_block, upper_block, d, d_inv, lower, upper);
}
}  // namespace internal

GaussSeidelPreconditioner::GaussSeidelPreconditioner(const SplitRows& split) {
  avx2_ = base::CpuHasAvx2();
  const int rows = static_cast<int>(split.general_start.size()) - 1;
  diag_slot_.assign(static_cast<std::size_t>(rows), 0);
  row_data_.assign(static_cast<std::size_t>(rows), internal::SweepRowData{});
  int num_slots = 0;  // the blocks' (those of the split: every slot)
  for (int r = 0; r < rows; ++r) {
    const auto row = static_cast<std::size_t>(r);
    num_slots =
        std::max(num_slots, split.general_first_slot[row] + split.general_start[row + 1] - split.general_start[row]);
  }
  for (int slot : split.scalar_slot) num_slots = std::max(num_slots, slot + 1);
  for (int r = 0; r < rows; ++r) {
    const auto row = static_cast<std::size_t>(r);
    int diag = -1;
    for (int k = split.general_start[row]; k < split.general_start[row + 1]; ++k) {
      const int c = split.general_col[static_cast<std::size_t>(k)];
      if (k > split.general_start[row]) {
        HAPTEX_DEMAND(split.general_col[static_cast<std::size_t>(k) - 1] < c);  // sorted
      }
      if (c == r) diag = k;
    }
    HAPTEX_DEMAND(diag >= 0);
    // Slot of general index k: k + slot_offset.
    const int slot_offset = split.general_first_slot[row] - split.general_start[row];
    diag_slot_[row] = slot_offset + diag;
    // Couplings to rows r - 1 and r + 1 through a general block: the sweeps apply them last.
    const int lower_adjacent =
        diag > split.general_start[row] && split.general_col[static_cast<std::size_t>(diag) - 1] == r - 1;
    const int upper_adjacent =
        diag + 1 < split.general_start[row + 1] && split.general_col[static_cast<std::size_t>(diag) + 1] == r + 1;
    int upper = split.scalar_start[row];
    for (int k = split.scalar_start[row]; k < split.scalar_start[row + 1]; ++k) {
      if (k > split.scalar_start[row]) {
        HAPTEX_DEMAND(split.scalar_col[static_cast<std::size_t>(k) - 1] <
                      split.scalar_col[static_cast<std::size_t>(k)]);
      }
      if (split.scalar_col[static_cast<std::size_t>(k)] < r) upper = k + 1;
    }
    // Forward: general blocks [g0, diag - lower_adjacent) and scalar blocks [s0, upper);
    // backward: [diag + 1 + upper_adjacent, g1) and [upper, s1).
    const auto shape = [&](int g0, int g1, int s0, int s1, int adjacent) {
      HAPTEX_DEMAND(g1 - g0 <= 255 && s1 - s0 <= 255);
      internal::SweepRow q{};
      q.block_bytes = static_cast<int>(sizeof(Eigen::Matrix3d)) * (slot_offset + g0);
      q.scalar_bytes = static_cast<int>(sizeof(double)) * s0;
      q.general = static_cast<unsigned char>(g1 - g0);
      q.scalars = static_cast<unsigned char>(s1 - s0);
      q.adjacent = static_cast<unsigned char>(adjacent);
      // The common shapes' last block is read 4-wide: another block must follow it in memory.
      const bool common =
          (q.general == 1 || q.general == 3) && q.scalars == 2 && adjacent != 0 && slot_offset + g1 < num_slots;
      q.common = common ? q.general : 0;
      std::vector<int> columns;
      for (int k = g0; k < g1; ++k) columns.push_back(4 * split.general_col[static_cast<std::size_t>(k)]);
      for (int k = s0; k < s1; ++k) columns.push_back(4 * split.scalar_col[static_cast<std::size_t>(k)]);
      if (common) {
        for (std::size_t k = 0; k < columns.size(); ++k) q.column[k] = columns[k];
      } else {
        q.column[0] = static_cast<int>(column_offset_.size());
        column_offset_.insert(column_offset_.end(), columns.begin(), columns.end());
      }
      return q;
    };
    row_data_[row].shape[0] =
        shape(split.general_start[row], diag - lower_adjacent, split.scalar_start[row], upper, lower_adjacent);
    row_data_[row].shape[1] = shape(diag + 1 + upper_adjacent, split.general_start[row + 1], upper,
                                    split.scalar_start[row + 1], upper_adjacent);
  }
  row_free_.assign(static_cast<std::size_t>(rows), 0);
  row_zero_.assign(static_cast<std::size_t>(rows), 1);          // row_data_ starts all 0
  runs_.assign(2 * static_cast<std::size_t>(rows / 2 + 1), 0);  // at most every other row starts a run
}

bool GaussSeidelPreconditioner::UpdateRows(const std::vector<Eigen::Matrix3d>& blocks, double omega) {
  diag_excess_ = 2.0 - omega;
  const RowUpdate u{diag_slot_.data(), row_free_.data(), blocks.data(),    omega,
                    1.0 / omega,       rows(),           row_data_.data(), row_zero_.data()};
#ifdef HAPTEX_X86_KERNELS
  if (avx2_) return RowUpdatesAvx2(u);
#endif
  return RowUpdatesGeneric(u);
}

internal::GaussSeidelSweepArgs GaussSeidelPreconditioner::Args(const std::vector<Eigen::Matrix3d>& blocks,
                                                               const std::vector<double>& scalars) const {
  return {row_data_.data(), column_offset_.data(), blocks.data(), scalars.data(), rows(), runs_.data(),
          num_runs_,        diag_excess_,          avx2_};
}

namespace {
void DemandRows(const PaddedVector& v, int rows) { HAPTEX_DEMAND(v.rows() == rows); }
}  // namespace

void GaussSeidelPreconditioner::ForwardSolve(const std::vector<Eigen::Matrix3d>& blocks,
                                             const std::vector<double>& scalars, const PaddedVector& x,
                                             PaddedVector* y) const {
  DemandRows(x, rows());
  DemandRows(*y, rows());
  Sweep<SweepKind::kForward>(Args(blocks, scalars), {x.data(), y->data(), nullptr, nullptr, nullptr, 0.0});
}

double GaussSeidelPreconditioner::ForwardSolveDiagonal(const std::vector<Eigen::Matrix3d>& blocks,
                                                       const std::vector<double>& scalars, const PaddedVector& x,
                                                       PaddedVector* y, PaddedVector* w) const {
  DemandRows(x, rows());
  DemandRows(*y, rows());
  DemandRows(*w, rows());
  return Sweep<SweepKind::kForwardDiagonal>(Args(blocks, scalars),
                                            {x.data(), y->data(), nullptr, w->data(), nullptr, 0.0});
}

void GaussSeidelPreconditioner::ForwardSolveDiagonalPair(const std::vector<Eigen::Matrix3d>& blocks,
                                                         const std::vector<double>& scalars, const PaddedVector& x0,
                                                         PaddedVector* y0, PaddedVector* w0, const PaddedVector& x1,
                                                         PaddedVector* y1, PaddedVector* w1, double* yw) const {
  for (const PaddedVector* v : {&x0, static_cast<const PaddedVector*>(y0), static_cast<const PaddedVector*>(w0), &x1,
                                static_cast<const PaddedVector*>(y1), static_cast<const PaddedVector*>(w1)}) {
    DemandRows(*v, rows());
  }
  SweepForwardDiagonalPair(Args(blocks, scalars), {x0.data(), y0->data(), nullptr, w0->data(), nullptr, 0.0},
                           {x1.data(), y1->data(), nullptr, w1->data(), nullptr, 0.0}, yw);
}

void GaussSeidelPreconditioner::BackwardSolve(const std::vector<Eigen::Matrix3d>& blocks,
                                              const std::vector<double>& scalars, const PaddedVector& x,
                                              PaddedVector* y) const {
  DemandRows(x, rows());
  DemandRows(*y, rows());
  Sweep<SweepKind::kBackward>(Args(blocks, scalars), {x.data(), y->data(), nullptr, nullptr, nullptr, 0.0});
}

double GaussSeidelPreconditioner::MultiplySplit(const std::vector<Eigen::Matrix3d>& blocks,
                                                const std::vector<double>& scalars, const PaddedVector& x,
                                                PaddedVector* t, PaddedVector* z, PaddedVector* y) const {
  for (const PaddedVector* v : {&x, static_cast<const PaddedVector*>(t), static_cast<const PaddedVector*>(z),
                                static_cast<const PaddedVector*>(y)}) {
    DemandRows(*v, rows());
  }
  const SweepVectors v{x.data(), y->data(), t->data(), z->data(), nullptr, 0.0};
  Sweep<SweepKind::kEisenstatBackward>(Args(blocks, scalars), v);
  return Sweep<SweepKind::kEisenstatForward>(Args(blocks, scalars), v);
}

double GaussSeidelPreconditioner::UpdateMultiplySplit(const std::vector<Eigen::Matrix3d>& blocks,
                                                      const std::vector<double>& scalars, const PaddedVector& s,
                                                      double beta, PaddedVector* x, PaddedVector* t, PaddedVector* z,
                                                      PaddedVector* y) const {
  for (const PaddedVector* v : {&s, static_cast<const PaddedVector*>(x), static_cast<const PaddedVector*>(t),
                                static_cast<const PaddedVector*>(z), static_cast<const PaddedVector*>(y)}) {
    DemandRows(*v, rows());
  }
  const SweepVectors v{x->data(), y->data(), t->data(), z->data(), s.data(), beta, x->data()};
  Sweep<SweepKind::kEisenstatBackwardUpdate>(Args(blocks, scalars), v);
  return Sweep<SweepKind::kEisenstatForward>(Args(blocks, scalars), v);
}

double GaussSeidelPreconditioner::MultiplyDiagonal(const PaddedVector& x, PaddedVector* y) const {
  DemandRows(x, rows());
  DemandRows(*y, rows());
  const int rows = this->rows();
  const double* xp = x.data();
  double* yp = y->data();
#ifdef HAPTEX_X86_KERNELS
  if (avx2_) return MultiplyDiagonalAvx2(row_data_.data(), rows, xp, yp);
#endif
  double xy = 0.0;
  for (int r = 0; r < rows; ++r) {
    xy += DiagonalRowGeneric(row_data_[static_cast<std::size_t>(r)].diag, xp + 4 * r, yp + 4 * r);
  }
  return xy;
}

double GaussSeidelPreconditioner::StepResidual(double alpha, const PaddedVector& t, const PaddedVector& q, bool y_zero,
                                               PaddedVector* y, PaddedVector* r, PaddedVector* s) const {
  for (const PaddedVector* v : {&t, &q, static_cast<const PaddedVector*>(y), static_cast<const PaddedVector*>(r),
                                static_cast<const PaddedVector*>(s)}) {
    DemandRows(*v, rows());
  }
  const int rows = this->rows();
  const double* tp = t.data();
  const double* qp = q.data();
  double* yp = y->data();
  double* rp = r->data();
  double* sp = s->data();
  // The free rows' runs; all rows for a non-finite alpha (0 x alpha is not 0 then).
  const int all[2] = {0, rows};
  const bool every_row = !std::isfinite(alpha);
  const int* runs = every_row ? all : runs_.data();
  const int num_runs = every_row ? 1 : num_runs_;
#ifdef HAPTEX_X86_KERNELS
  if (avx2_) {
    return y_zero ? StepResidualAvx2<true>(row_data_.data(), runs, num_runs, rows, alpha, tp, qp, yp, rp, sp)
                  : StepResidualAvx2<false>(row_data_.data(), runs, num_runs, rows, alpha, tp, qp, yp, rp, sp);
  }
#endif
  double xy = 0.0;
  int done = 0;
  for (int run = 0; run < num_runs; ++run) {
    const int r0 = runs[2 * run], r1 = runs[2 * run + 1];
    if (y_zero) ZeroRows(yp, done, r0);
    for (int i = 4 * r0; i < 4 * r1; i += 4) {
      for (int k = 0; k < 4; ++k) {
        yp[i + k] = (y_zero ? 0.0 : yp[i + k]) + alpha * tp[i + k];
        rp[i + k] -= alpha * qp[i + k];
      }
      xy += DiagonalRowGeneric(row_data_[static_cast<std::size_t>(i / 4)].diag, rp + i, sp + i);
    }
    done = r1;
  }
  if (y_zero) ZeroRows(yp, done, rows);
  return xy;
}

}  // namespace haptex::textile
