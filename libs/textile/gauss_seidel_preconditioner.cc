#include "libs/textile/gauss_seidel_preconditioner.h"

#include "libs/textile/check.h"
#include "libs/textile/cpu_features.h"

#ifdef HAPTEX_TEXTILE_X86_KERNELS
#include <immintrin.h>
#endif

namespace haptex::textile {
namespace {

using internal::GaussSeidelSweepArgs;
using internal::PaddedBlock;

enum class SweepKind {
  kForward,    // y = (D_w + L)^-1 x
  kBackward,   // y = (D_w + U)^-1 x
  // Eisenstat's backward half: t = (D_w + U)^-1 x, and z = x - (2 - omega) D_w t in the same
  // pass (0 in rows that are not free, where x and D_w are 0).
  kEisenstatBackward,
  // Eisenstat's forward half: w = (D_w + L)^-1 z, kept in z (row r's z is dead once read),
  // y = w + t, and the sum of x . y.
  kEisenstatForward,
};

constexpr bool IsForward(SweepKind k) {
  return k == SweepKind::kForward || k == SweepKind::kEisenstatForward;
}

// Where row r's sums run: the general and scalar blocks on the sweep's side of the diagonal,
// except the block coupling to the row solved just before (r - 1 forward, r + 1 backward). That
// one is applied last, premultiplied by D_w^-1, so the serial dependency from row to row is one
// 3x3 product.
struct RowRange {
  const int* g_col;  // general and scalar blocks' columns
  const int* s_col;
  int g0, g1, s0, s1;
  bool adjacent;
  const Eigen::Matrix3d* blocks;  // offset so that general index k is blocks[k]
  const PaddedBlock* adjacent_scaled;
};

// The vector a sweep solves into, whose earlier rows its sums read: y, t, or w kept in z.
template <SweepKind kKind>
inline double* Solved(double* y, double* t, double* z) {
  return kKind == SweepKind::kEisenstatForward ? z : kKind == SweepKind::kEisenstatBackward ? t : y;
}

template <SweepKind kKind>
inline RowRange RangeOf(const GaussSeidelSweepArgs& a, int r) {
  constexpr bool kForward = IsForward(kKind);
  const SplitRows& s = *a.split;
  const auto row = static_cast<std::size_t>(r);
  RowRange q;
  q.g_col = s.general_col.data();
  q.s_col = s.scalar_col.data();
  q.adjacent = (kForward ? a.adjacent_lower : a.adjacent_upper)[row] != 0;
  q.g0 = kForward ? s.general_start[row] : a.general_diag[row] + 1 + (q.adjacent ? 1 : 0);
  q.g1 = kForward ? a.general_diag[row] - (q.adjacent ? 1 : 0) : s.general_start[row + 1];
  q.s0 = kForward ? s.scalar_start[row] : a.scalar_upper[row];
  q.s1 = kForward ? a.scalar_upper[row] : s.scalar_start[row + 1];
  q.blocks = a.blocks + s.general_first_slot[row] - s.general_start[row];
  q.adjacent_scaled = (kForward ? a.adjacent_lower_scaled : a.adjacent_upper_scaled) + row;
  return q;
}

// One row of a sweep, portable. Per component i, in this order (the AVX2 row does the same
// operations, lane i for component i, so both give identical results):
//   c_j = sum over the general blocks of m(i, j) y_j (j = 0, 1, 2, each its own sum)
//   acc = x - ((c_0 + c_1) + c_2) - sum over the scalar blocks of v y
//   o   = ((Dinv(i,0) acc_0 + Dinv(i,1) acc_1) + Dinv(i,2) acc_2)
//         - ((G(i,0) p_0 + G(i,1) p_1) + G(i,2) p_2)      (p: the row solved just before)
template <SweepKind kKind>
inline double RowGeneric(const GaussSeidelSweepArgs& a, int r, const double* x, double* y,
                         double* t, double* z) {
  constexpr bool kForward = IsForward(kKind);
  double* solved = Solved<kKind>(y, t, z);
  const double* in = kKind == SweepKind::kEisenstatForward ? z : x;
  const RowRange q = RangeOf<kKind>(a, r);
  double c[3][3] = {};
  for (int k = q.g0; k < q.g1; ++k) {
    const double* m = q.blocks[k].data();
    const double* yc = solved + 3 * q.g_col[k];
    for (int j = 0; j < 3; ++j) {
      for (int i = 0; i < 3; ++i) c[j][i] += m[3 * j + i] * yc[j];
    }
  }
  double sc[3] = {};
  for (int k = q.s0; k < q.s1; ++k) {
    const double* yc = solved + 3 * q.s_col[k];
    for (int i = 0; i < 3; ++i) sc[i] += a.scalars[k] * yc[i];
  }
  double acc[3];
  for (int i = 0; i < 3; ++i) acc[i] = (in[3 * r + i] - ((c[0][i] + c[1][i]) + c[2][i])) - sc[i];
  const PaddedBlock& inv = a.diag_inv[r];
  double o[3];
  for (int i = 0; i < 3; ++i) {
    o[i] = (inv.col[0][i] * acc[0] + inv.col[1][i] * acc[1]) + inv.col[2][i] * acc[2];
  }
  if (q.adjacent) {
    const double* p = solved + 3 * (kForward ? r - 1 : r + 1);
    const PaddedBlock& g = *q.adjacent_scaled;
    for (int i = 0; i < 3; ++i) o[i] -= (g.col[0][i] * p[0] + g.col[1][i] * p[1]) + g.col[2][i] * p[2];
  }
  for (int i = 0; i < 3; ++i) solved[3 * r + i] = o[i];
  if constexpr (kKind == SweepKind::kEisenstatBackward) {
    const PaddedBlock& d = a.diag[r];
    for (int i = 0; i < 3; ++i) {
      z[3 * r + i] = x[3 * r + i] - a.diag_excess * ((d.col[0][i] * o[0] + d.col[1][i] * o[1]) + d.col[2][i] * o[2]);
    }
  } else if constexpr (kKind == SweepKind::kEisenstatForward) {
    double yr[3];
    for (int i = 0; i < 3; ++i) {
      yr[i] = o[i] + t[3 * r + i];
      y[3 * r + i] = yr[i];
    }
    return (x[3 * r] * yr[0] + x[3 * r + 1] * yr[1]) + x[3 * r + 2] * yr[2];
  }
  return 0.0;
}

#ifdef HAPTEX_TEXTILE_X86_KERNELS
// The row in 4-wide registers: lanes 0..2 are components 0..2, lane 3 is never stored. No FMA
// (target avx2 only): products round as in RowGeneric.
template <SweepKind kKind>
__attribute__((target("avx2"))) inline double RowAvx2(const GaussSeidelSweepArgs& a, int r,
                                                      const double* x, double* y, double* t,
                                                      double* z) {
  constexpr bool kForward = IsForward(kKind);
  double* solved = Solved<kKind>(y, t, z);
  const double* in = kKind == SweepKind::kEisenstatForward ? z : x;
  const RowRange q = RangeOf<kKind>(a, r);
  const __m256i three = _mm256_set_epi64x(0, -1, -1, -1);
  __m256d c0 = _mm256_setzero_pd(), c1 = _mm256_setzero_pd(), c2 = _mm256_setzero_pd();
  for (int k = q.g0; k < q.g1; ++k) {
    const double* m = q.blocks[k].data();
    const double* yc = solved + 3 * q.g_col[k];
    c0 = _mm256_add_pd(c0, _mm256_mul_pd(_mm256_loadu_pd(m), _mm256_broadcast_sd(yc)));
    c1 = _mm256_add_pd(c1, _mm256_mul_pd(_mm256_loadu_pd(m + 3), _mm256_broadcast_sd(yc + 1)));
    c2 = _mm256_add_pd(c2, _mm256_mul_pd(_mm256_maskload_pd(m + 6, three), _mm256_broadcast_sd(yc + 2)));
  }
  __m256d sc = _mm256_setzero_pd();
  for (int k = q.s0; k < q.s1; ++k) {
    sc = _mm256_add_pd(sc, _mm256_mul_pd(_mm256_broadcast_sd(a.scalars + k),
                                         _mm256_maskload_pd(solved + 3 * q.s_col[k], three)));
  }
  const __m256d acc = _mm256_sub_pd(
      _mm256_sub_pd(_mm256_maskload_pd(in + 3 * r, three), _mm256_add_pd(_mm256_add_pd(c0, c1), c2)), sc);
  const PaddedBlock& inv = a.diag_inv[r];
  __m256d o = _mm256_add_pd(
      _mm256_add_pd(_mm256_mul_pd(_mm256_load_pd(inv.col[0]), _mm256_permute4x64_pd(acc, 0x00)),
                    _mm256_mul_pd(_mm256_load_pd(inv.col[1]), _mm256_permute4x64_pd(acc, 0x55))),
      _mm256_mul_pd(_mm256_load_pd(inv.col[2]), _mm256_permute4x64_pd(acc, 0xAA)));
  if (q.adjacent) {
    const double* p = solved + 3 * (kForward ? r - 1 : r + 1);
    const PaddedBlock& g = *q.adjacent_scaled;
    o = _mm256_sub_pd(
        o, _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(_mm256_load_pd(g.col[0]), _mm256_broadcast_sd(p)),
                                       _mm256_mul_pd(_mm256_load_pd(g.col[1]), _mm256_broadcast_sd(p + 1))),
                         _mm256_mul_pd(_mm256_load_pd(g.col[2]), _mm256_broadcast_sd(p + 2))));
  }
  _mm256_maskstore_pd(solved + 3 * r, three, o);
  if constexpr (kKind == SweepKind::kEisenstatBackward) {
    const PaddedBlock& d = a.diag[r];
    const __m256d dt = _mm256_add_pd(
        _mm256_add_pd(_mm256_mul_pd(_mm256_load_pd(d.col[0]), _mm256_permute4x64_pd(o, 0x00)),
                      _mm256_mul_pd(_mm256_load_pd(d.col[1]), _mm256_permute4x64_pd(o, 0x55))),
        _mm256_mul_pd(_mm256_load_pd(d.col[2]), _mm256_permute4x64_pd(o, 0xAA)));
    _mm256_maskstore_pd(z + 3 * r, three,
                        _mm256_sub_pd(_mm256_maskload_pd(x + 3 * r, three),
                                      _mm256_mul_pd(_mm256_set1_pd(a.diag_excess), dt)));
  } else if constexpr (kKind == SweepKind::kEisenstatForward) {
    const __m256d yr = _mm256_add_pd(o, _mm256_maskload_pd(t + 3 * r, three));
    _mm256_maskstore_pd(y + 3 * r, three, yr);
    alignas(32) double xy[4];
    _mm256_store_pd(xy, _mm256_mul_pd(_mm256_maskload_pd(x + 3 * r, three), yr));
    return (xy[0] + xy[1]) + xy[2];
  }
  return 0.0;
}

template <SweepKind kKind>
__attribute__((target("avx2"))) double SweepAvx2(const GaussSeidelSweepArgs& a, const double* x,
                                                 double* y, double* t, double* z) {
  double xy = 0.0;
  for (int i = 0; i < a.rows; ++i) xy += RowAvx2<kKind>(a, IsForward(kKind) ? i : a.rows - 1 - i, x, y, t, z);
  return xy;
}

#endif

template <SweepKind kKind>
double Sweep(const GaussSeidelSweepArgs& a, const double* x, double* y, double* t, double* z) {
#ifdef HAPTEX_TEXTILE_X86_KERNELS
  if (a.avx2) return SweepAvx2<kKind>(a, x, y, t, z);
#endif
  double xy = 0.0;
  for (int i = 0; i < a.rows; ++i) xy += RowGeneric<kKind>(a, IsForward(kKind) ? i : a.rows - 1 - i, x, y, t, z);
  return xy;
}

}  // namespace

GaussSeidelPreconditioner::GaussSeidelPreconditioner(const SplitRows& split) {
  avx2_ = internal::CpuHasAvx2();
  const int rows = static_cast<int>(split.general_start.size()) - 1;
  general_diag_.assign(static_cast<std::size_t>(rows), 0);
  scalar_upper_.assign(static_cast<std::size_t>(rows), 0);
  adjacent_lower_.assign(static_cast<std::size_t>(rows), 0);
  adjacent_upper_.assign(static_cast<std::size_t>(rows), 0);
  for (int r = 0; r < rows; ++r) {
    const auto row = static_cast<std::size_t>(r);
    int diag = -1;
    for (int k = split.general_start[row]; k < split.general_start[row + 1]; ++k) {
      const int c = split.general_col[static_cast<std::size_t>(k)];
      if (k > split.general_start[row]) {
        HAPTEX_TEXTILE_DEMAND(split.general_col[static_cast<std::size_t>(k) - 1] < c);  // sorted
      }
      if (c == r) diag = k;
    }
    HAPTEX_TEXTILE_DEMAND(diag >= 0);
    general_diag_[row] = diag;
    if (diag > split.general_start[row] && split.general_col[static_cast<std::size_t>(diag) - 1] == r - 1) {
      adjacent_lower_[row] = 1;
    }
    if (diag + 1 < split.general_start[row + 1] && split.general_col[static_cast<std::size_t>(diag) + 1] == r + 1) {
      adjacent_upper_[row] = 1;
    }
    int upper = split.scalar_start[row];
    for (int k = split.scalar_start[row]; k < split.scalar_start[row + 1]; ++k) {
      if (k > split.scalar_start[row]) {
        HAPTEX_TEXTILE_DEMAND(split.scalar_col[static_cast<std::size_t>(k) - 1] <
                              split.scalar_col[static_cast<std::size_t>(k)]);
      }
      if (split.scalar_col[static_cast<std::size_t>(k)] < r) upper = k + 1;
    }
    scalar_upper_[row] = upper;
  }
  diag_.assign(static_cast<std::size_t>(rows), internal::PaddedBlock{});
  diag_inv_ = diag_;
  adjacent_lower_scaled_ = diag_;
  adjacent_upper_scaled_ = diag_;
}

internal::GaussSeidelSweepArgs GaussSeidelPreconditioner::Args(const SplitRows& split, const std::vector<Eigen::Matrix3d>& blocks,
                                          const std::vector<double>& scalars) const {
  return {&split, general_diag_.data(), scalar_upper_.data(), adjacent_lower_.data(),
          adjacent_upper_.data(), diag_.data(), diag_inv_.data(), adjacent_lower_scaled_.data(),
          adjacent_upper_scaled_.data(), blocks.data(), scalars.data(),
          static_cast<int>(general_diag_.size()), diag_excess_, avx2_};
}

void GaussSeidelPreconditioner::ForwardSolve(const SplitRows& split, const std::vector<Eigen::Matrix3d>& blocks,
                                             const std::vector<double>& scalars,
                                             const Eigen::VectorXd& x, Eigen::VectorXd* y) const {
  Sweep<SweepKind::kForward>(Args(split, blocks, scalars), x.data(), y->data(), nullptr, nullptr);
}

void GaussSeidelPreconditioner::BackwardSolve(const SplitRows& split, const std::vector<Eigen::Matrix3d>& blocks,
                                              const std::vector<double>& scalars,
                                              const Eigen::VectorXd& x, Eigen::VectorXd* y) const {
  Sweep<SweepKind::kBackward>(Args(split, blocks, scalars), x.data(), y->data(), nullptr, nullptr);
}

double GaussSeidelPreconditioner::MultiplySplit(const SplitRows& split, const std::vector<Eigen::Matrix3d>& blocks,
                                                const std::vector<double>& scalars,
                                                const Eigen::VectorXd& x, Eigen::VectorXd* t,
                                                Eigen::VectorXd* z, Eigen::VectorXd* y) const {
  const internal::GaussSeidelSweepArgs args = Args(split, blocks, scalars);
  Sweep<SweepKind::kEisenstatBackward>(args, x.data(), nullptr, t->data(), z->data());
  return Sweep<SweepKind::kEisenstatForward>(args, x.data(), y->data(), t->data(), z->data());
}

double GaussSeidelPreconditioner::MultiplyDiagonal(const Eigen::VectorXd& x, Eigen::VectorXd* y) const {
  const int rows = static_cast<int>(general_diag_.size());
  const double* xp = x.data();
  double* yp = y->data();
  double xy = 0.0;
  for (int r = 0; r < rows; ++r) {
    const internal::PaddedBlock& d = diag_[static_cast<std::size_t>(r)];
    const double* xr = xp + 3 * r;
    for (int i = 0; i < 3; ++i) {
      yp[3 * r + i] = (d.col[0][i] * xr[0] + d.col[1][i] * xr[1]) + d.col[2][i] * xr[2];
      xy += xr[i] * yp[3 * r + i];
    }
  }
  return xy;
}

}  // namespace haptex::textile
