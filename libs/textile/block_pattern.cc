#include "libs/textile/block_pattern.h"

#include <algorithm>
#include <utility>

#include "libs/base/demand.h"

#include "libs/base/cpu_features.h"

#ifdef HAPTEX_X86_KERNELS
#include <immintrin.h>
#endif

namespace haptex::textile {

int BlockPattern::Slot(int r, int c) const {
  // Linear: rows are short, and MoveToRowEnds leaves them in two sorted groups.
  const auto begin = cols.begin() + row_start[static_cast<std::size_t>(r)];
  const auto end = cols.begin() + row_start[static_cast<std::size_t>(r) + 1];
  const auto it = std::find(begin, end, c);
  HAPTEX_DEMAND(it != end);
  return static_cast<int>(it - cols.begin());
}

void BlockPattern::MoveToRowEnds(const std::vector<unsigned char>& to_end) {
  HAPTEX_DEMAND(to_end.size() == cols.size());
  std::vector<int> reordered;
  reordered.reserve(cols.size());
  for (int r = 0; r < rows(); ++r) {
    const auto row = static_cast<std::size_t>(r);
    const int k0 = row_start[row], k1 = row_start[row + 1];
    for (int pass = 0; pass < 2; ++pass) {
      for (int k = k0; k < k1; ++k) {
        if ((to_end[static_cast<std::size_t>(k)] != 0) == (pass == 1)) {
          reordered.push_back(cols[static_cast<std::size_t>(k)]);
        }
      }
    }
  }
  cols = std::move(reordered);
  for (int r = 0; r < rows(); ++r) diag_slot[static_cast<std::size_t>(r)] = Slot(r, r);
}

BlockPattern BlockPattern::FromPairs(int rows, const std::vector<std::pair<int, int>>& pairs) {
  std::vector<std::vector<int>> adj(static_cast<std::size_t>(rows));
  for (int r = 0; r < rows; ++r) adj[static_cast<std::size_t>(r)].push_back(r);
  for (const auto& [i, j] : pairs) {
    HAPTEX_DEMAND(i >= 0 && i < rows && j >= 0 && j < rows);
    adj[static_cast<std::size_t>(i)].push_back(j);
    adj[static_cast<std::size_t>(j)].push_back(i);
  }
  BlockPattern p;
  p.row_start.assign(static_cast<std::size_t>(rows) + 1, 0);
  p.diag_slot.assign(static_cast<std::size_t>(rows), 0);
  for (int r = 0; r < rows; ++r) {
    auto& a = adj[static_cast<std::size_t>(r)];
    std::sort(a.begin(), a.end());
    a.erase(std::unique(a.begin(), a.end()), a.end());
    p.row_start[static_cast<std::size_t>(r) + 1] =
        p.row_start[static_cast<std::size_t>(r)] + static_cast<int>(a.size());
    p.cols.insert(p.cols.end(), a.begin(), a.end());
  }
  for (int r = 0; r < rows; ++r) p.diag_slot[static_cast<std::size_t>(r)] = p.Slot(r, r);
  return p;
}

SplitRows SplitRows::FromPattern(const BlockPattern& pattern, const std::vector<unsigned char>& is_scalar) {
  HAPTEX_DEMAND(is_scalar.size() == pattern.cols.size());
  SplitRows s;
  s.general_start.push_back(0);
  s.general_first_slot.assign(static_cast<std::size_t>(pattern.rows()), 0);
  s.scalar_start.push_back(0);
  for (int r = 0; r < pattern.rows(); ++r) {
    for (int k = pattern.row_start[static_cast<std::size_t>(r)]; k < pattern.row_start[static_cast<std::size_t>(r) + 1];
         ++k) {
      const int c = pattern.cols[static_cast<std::size_t>(k)];
      if (is_scalar[static_cast<std::size_t>(k)]) {
        HAPTEX_DEMAND(c != r);
        s.scalar_slot.push_back(k);
        s.scalar_col.push_back(c);
      } else {
        const int g = static_cast<int>(s.general_col.size()) - s.general_start.back();
        if (g == 0) s.general_first_slot[static_cast<std::size_t>(r)] = k;
        HAPTEX_DEMAND(k == s.general_first_slot[static_cast<std::size_t>(r)] + g);  // contiguous
        s.general_col.push_back(c);
      }
    }
    s.general_start.push_back(static_cast<int>(s.general_col.size()));
    s.scalar_start.push_back(static_cast<int>(s.scalar_slot.size()));
  }
  return s;
}

namespace internal {
namespace {

// Scalar blocks of row r, then x_r . y_r.
inline double FinishRow(const SplitRows& split, const double* scalars, const double* x, int r, double acc[3],
                        double* y) {
  const int* s_col = split.scalar_col.data();
  for (int k = split.scalar_start[static_cast<std::size_t>(r)]; k < split.scalar_start[static_cast<std::size_t>(r) + 1];
       ++k) {
    const double* xc = x + 3 * s_col[k];
    const double v = scalars[k];
    acc[0] += v * xc[0];
    acc[1] += v * xc[1];
    acc[2] += v * xc[2];
  }
  y[3 * r] = acc[0];
  y[3 * r + 1] = acc[1];
  y[3 * r + 2] = acc[2];
  return x[3 * r] * acc[0] + x[3 * r + 1] * acc[1] + x[3 * r + 2] * acc[2];
}

double RangeGeneric(const SplitRows& split, const Eigen::Matrix3d* blocks, const double* scalars, const double* x,
                    double* y, int r0, int r1) {
  const int* g_start = split.general_start.data();
  const int* g_first = split.general_first_slot.data();
  const int* g_col = split.general_col.data();
  double xy = 0.0;
  for (int r = r0; r < r1; ++r) {
    // c[b][j][i]: column j of the row's even (b = 0) or odd (b = 1) blocks, row i.
    double c[2][3][3] = {};
    const double* m = blocks[g_first[r]].data();
    for (int k = g_start[r]; k < g_start[r + 1]; ++k, m += 9) {
      const double* xc = x + 3 * g_col[k];
      double(&cb)[3][3] = c[(k - g_start[r]) & 1];
      for (int j = 0; j < 3; ++j) {
        for (int i = 0; i < 3; ++i) cb[j][i] += m[3 * j + i] * xc[j];
      }
    }
    double acc[3];
    for (int i = 0; i < 3; ++i) {
      acc[i] = ((c[0][0][i] + c[1][0][i]) + (c[0][1][i] + c[1][1][i])) + (c[0][2][i] + c[1][2][i]);
    }
    xy += FinishRow(split, scalars, x, r, acc, y);
  }
  return xy;
}

#ifdef HAPTEX_X86_KERNELS
// One block's columns times x_c's entries, added to (c0, c1, c2): column 0 and 1 are loaded
// from m and m + 3 (lanes 0..2 are rows 0..2), column 2 from m + 5 (lanes 1..3 are rows 0..2),
// so no load leaves the block. No FMA: the products round as in RangeGeneric.
__attribute__((target("avx"), always_inline)) inline void BlockAvx(const double* m, const double* xc, __m256d* c0,
                                                                   __m256d* c1, __m256d* c2) {
  *c0 = _mm256_add_pd(*c0, _mm256_mul_pd(_mm256_loadu_pd(m), _mm256_broadcast_sd(xc)));
  *c1 = _mm256_add_pd(*c1, _mm256_mul_pd(_mm256_loadu_pd(m + 3), _mm256_broadcast_sd(xc + 1)));
  *c2 = _mm256_add_pd(*c2, _mm256_mul_pd(_mm256_loadu_pd(m + 5), _mm256_broadcast_sd(xc + 2)));
}

// The same sums, one 4-wide multiply and add per block column (BlockAvx). The counts of a
// grid's interior rows (9 general, 4 scalar blocks) get fixed-trip code behind one
// well-predicted branch each: variable-trip loops mispredict at each row's end.
__attribute__((target("avx"))) double RangeAvx(const SplitRows& split, const Eigen::Matrix3d* blocks,
                                               const double* scalars, const double* x, double* y, int r0, int r1) {
  const int* g_start = split.general_start.data();
  const int* g_first = split.general_first_slot.data();
  const int* g_col = split.general_col.data();
  const int* s_start = split.scalar_start.data();
  const int* s_col = split.scalar_col.data();
  const __m256i three = _mm256_set_epi64x(0, -1, -1, -1);
  const int last_row = static_cast<int>(split.general_start.size()) - 2;
  double xy = 0.0;
  for (int r = r0; r < r1; ++r) {
    // Even and odd blocks in separate accumulators: six independent chains of adds.
    __m256d c0 = _mm256_setzero_pd(), c1 = _mm256_setzero_pd(), c2 = _mm256_setzero_pd();
    __m256d d0 = _mm256_setzero_pd(), d1 = _mm256_setzero_pd(), d2 = _mm256_setzero_pd();
    const double* m = blocks[g_first[r]].data();
    const int* col = g_col + g_start[r];
    const int count = g_start[r + 1] - g_start[r];
    if (count == 9) {
#pragma GCC unroll 4
      for (int k = 0; k < 8; k += 2) {
        BlockAvx(m + 9 * k, x + 3 * col[k], &c0, &c1, &c2);
        BlockAvx(m + 9 * k + 9, x + 3 * col[k + 1], &d0, &d1, &d2);
      }
      BlockAvx(m + 72, x + 3 * col[8], &c0, &c1, &c2);
    } else {
      int k = 0;
      for (; k + 1 < count; k += 2, m += 18) {
        BlockAvx(m, x + 3 * col[k], &c0, &c1, &c2);
        BlockAvx(m + 9, x + 3 * col[k + 1], &d0, &d1, &d2);
      }
      if (k < count) BlockAvx(m, x + 3 * col[k], &c0, &c1, &c2);
    }
    const __m256d s01 = _mm256_add_pd(_mm256_add_pd(c0, d0), _mm256_add_pd(c1, d1));
    const __m256d s2 = _mm256_add_pd(c2, d2);
    // acc_i = s01_i + s2_(i+1): s2's lanes 1..3 moved down to 0..2 (lane 3: 0).
    const __m256d s2_high = _mm256_permute2f128_pd(s2, s2, 0x81);  // (s2_2, s2_3, 0, 0)
    __m256d acc = _mm256_add_pd(s01, _mm256_shuffle_pd(s2, s2_high, 0x5));
    // FinishRow's sums in its order, lane i for component i (x's rows read 3 wide: the last
    // row has no 4th entry).
    const int j0 = s_start[r], scalar_count = s_start[r + 1] - j0;
    const double* v = scalars + j0;
    const int* s_c = s_col + j0;
    if (scalar_count == 4 && s_c[3] < last_row) {
      // Columns sorted: none is the last row, so 4-wide loads stay inside x (lane 3 as above).
#pragma GCC unroll 4
      for (int j = 0; j < 4; ++j) {
        acc = _mm256_add_pd(acc, _mm256_mul_pd(_mm256_broadcast_sd(v + j), _mm256_loadu_pd(x + 3 * s_c[j])));
      }
    } else {
      for (int j = 0; j < scalar_count; ++j) {
        acc = _mm256_add_pd(acc, _mm256_mul_pd(_mm256_broadcast_sd(v + j), _mm256_maskload_pd(x + 3 * s_c[j], three)));
      }
    }
    const __m128d acc01 = _mm256_castpd256_pd128(acc), acc2 = _mm256_extractf128_pd(acc, 1);
    _mm_storeu_pd(y + 3 * r, acc01);
    _mm_store_sd(y + 3 * r + 2, acc2);
    // x_r . y_r as (x_0 y_0 + x_1 y_1) + x_2 y_2.
    const __m256d p = _mm256_mul_pd(_mm256_maskload_pd(x + 3 * r, three), acc);
    const __m128d p01 = _mm256_castpd256_pd128(p);
    xy += _mm_cvtsd_f64(_mm_add_sd(_mm_add_sd(p01, _mm_unpackhi_pd(p01, p01)), _mm256_extractf128_pd(p, 1)));
  }
  return xy;
}

#endif

}  // namespace

double MultiplySplitRowRange(const SplitRows& split, const Eigen::Matrix3d* blocks, const double* scalars,
                             const double* x, double* y, int r0, int r1) {
  return MultiplySplitRowRange(split, blocks, scalars, x, y, r0, r1, base::CpuHasAvx());
}

double MultiplySplitRowRange(const SplitRows& split, const Eigen::Matrix3d* blocks, const double* scalars,
                             const double* x, double* y, int r0, int r1, bool avx) {
#ifdef HAPTEX_X86_KERNELS
  if (avx) return RangeAvx(split, blocks, scalars, x, y, r0, r1);
#endif
  (void)avx;
  return RangeGeneric(split, blocks, scalars, x, y, r0, r1);
}

}  // namespace internal

}  // namespace haptex::textile
