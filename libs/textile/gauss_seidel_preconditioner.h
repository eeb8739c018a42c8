#pragma once
// Symmetric (block) Gauss-Seidel / SSOR preconditioning of the implicit system with Eisenstat's
// trick (Eisenstat 1981; Saad, "Iterative Methods for Sparse Linear Systems", section 9.2).
//
// With A = L + D + U (U = L^T) and D_w = D / omega, SSOR's preconditioner is
// M = (D_w + L) D_w^-1 (D_w + U). CG runs on the split system
//   A~ = (D_w + L)^-1 A (D_w + U)^-1,  preconditioned by D_w,
// and A~ c = t + (D_w + L)^-1 (c - (2 D_w - D) t) with t = (D_w + U)^-1 c: one backward and one
// forward triangular sweep over the off-diagonal blocks per iteration, the cost of about one
// product with A. On the tension-dominated grids of a fine patch it needs far fewer iterations
// than block Jacobi. The filter: rows that are not free take no part (their values stay 0).

#include <vector>

#include <Eigen/Core>

#include "libs/textile/block_pattern.h"
#include "libs/textile/padded_vector.h"

namespace haptex::textile {

namespace internal {
/// A 3x3 block with each column padded to 4 doubles (the 4th is 0): one aligned 4-wide load
/// per column.
struct PaddedBlock {
  alignas(32) double col[3][4] = {};
  void Set(const Eigen::Matrix3d& m) {
    for (int j = 0; j < 3; ++j) {
      for (int i = 0; i < 3; ++i) col[j][i] = m(i, j);
      col[j][3] = 0.0;
    }
  }
  void SetZero() {
    for (auto& c : col) c[0] = c[1] = c[2] = c[3] = 0.0;
  }
};

/// Where one row of a sweep sums (fixed per model, one record per row and direction): `general`
/// blocks from byte block_bytes of the blocks on and `scalars` scalar blocks from byte
/// scalar_bytes of the scalars on, those on the sweep's side of the diagonal, except the block
/// coupling to the row solved just before (r - 1 forward, r + 1 backward) when `adjacent`: that
/// one is applied last, premultiplied by D_w^-1, so the dependency from row to row is one 3x3
/// product. `common` (the shapes of a grid's inner rows: 1 or 3 general blocks, 2 scalar ones,
/// adjacent, a block after the last in memory) is its general count, and column[] holds the
/// columns' offsets in a padded vector (4 x column), general then scalar: the kernel reads them
/// with no indirection and no test. Other rows (common = 0): column[0] is the index of those
/// offsets in GaussSeidelSweepArgs::column_offset. 32 bytes.
struct SweepRow {
  int block_bytes, scalar_bytes;
  unsigned char general, scalars, adjacent, common;
  int column[5];
};

/// What the sweeps read of one row, together: one pointer walks them (index 0: forward, 1: backward).
struct SweepRowData {
  PaddedBlock diag_inv;  ///< D_w^-1 (zero for rows that are not free)
  /// D_w^-1 A(r, r - 1) and D_w^-1 A(r, r + 1) where those blocks exist (zero elsewhere, and
  /// for rows or neighbours that are not free).
  PaddedBlock adjacent_scaled[2];
  PaddedBlock diag;  ///< D_w (zero for rows that are not free)
  SweepRow shape[2];
};

/// What one triangular sweep reads (gauss_seidel_preconditioner.cc).
struct GaussSeidelSweepArgs {
  const SweepRowData* row;   ///< per row
  const int* column_offset;  ///< SweepRow::column's array for the uncommon rows
  const Eigen::Matrix3d* blocks;
  const double* scalars;
  int rows;
  /// The free rows as runs [runs[2i], runs[2i + 1]), i < num_runs, ascending: the sweeps skip
  /// the other rows (zeroing their outputs), and a run's first row has no solved neighbour.
  const int* runs;
  int num_runs;
  double diag_excess;
  bool avx2;  ///< the AVX2 kernel (else the portable one: same results)
};
}  // namespace internal

class GaussSeidelPreconditioner {
 public:
  GaussSeidelPreconditioner() = default;
  /// Records where each row's blocks switch from below to above the diagonal in `split`
  /// (each row's general and scalar columns sorted). Allocates; call once per model. Blocks
  /// passed later are in its pattern's slot order, scalars in its order.
  explicit GaussSeidelPreconditioner(const SplitRows& split);

  /// Inverts the (scaled) diagonal blocks of `blocks` for relaxation factor omega in (0, 2).
  /// Returns false if a free row's diagonal block is not invertible. Never allocates.
  template <typename RowFree>
  bool Update(const std::vector<Eigen::Matrix3d>& blocks, double omega, RowFree row_free);

  // The vectors below are padded (padded_vector.h), rows() rows each, and distinct.

  /// y = (D_w + L)^-1 x over the free rows (0 elsewhere; x must be 0 there). Never allocates.
  void ForwardSolve(const std::vector<Eigen::Matrix3d>& blocks, const std::vector<double>& scalars,
                    const PaddedVector& x, PaddedVector* y) const;
  /// y = (D_w + U)^-1 x over the free rows (0 elsewhere; x must be 0 there). Never allocates.
  void BackwardSolve(const std::vector<Eigen::Matrix3d>& blocks, const std::vector<double>& scalars,
                     const PaddedVector& x, PaddedVector* y) const;
  /// y = A~ x with A~ = (D_w + L)^-1 A (D_w + U)^-1; returns x . y. Leaves t = (D_w + U)^-1 x
  /// (CG keeps its unknown unsplit with it); `z` is scratch. Never allocates.
  double MultiplySplit(const std::vector<Eigen::Matrix3d>& blocks, const std::vector<double>& scalars,
                       const PaddedVector& x, PaddedVector* t, PaddedVector* z, PaddedVector* y) const;
  /// y = D_w x over the free rows (CG's preconditioner on A~); returns x . y. Never allocates.
  double MultiplyDiagonal(const PaddedVector& x, PaddedVector* y) const;

  // CG's passes fused with the above (one pass over the rows instead of several): the same
  // operations in the same order, so the same bits as the unfused calls.

  /// ForwardSolve(x, y), then MultiplyDiagonal(*y, w): returns y . w. Never allocates.
  double ForwardSolveDiagonal(const std::vector<Eigen::Matrix3d>& blocks, const std::vector<double>& scalars,
                              const PaddedVector& x, PaddedVector* y, PaddedVector* w) const;
  /// ForwardSolveDiagonal(x0, y0, w0) and ForwardSolveDiagonal(x1, y1, w1) in one pass (each
  /// block read once for both): yw[0] = y0 . w0, yw[1] = y1 . w1. Never allocates.
  void ForwardSolveDiagonalPair(const std::vector<Eigen::Matrix3d>& blocks, const std::vector<double>& scalars,
                                const PaddedVector& x0, PaddedVector* y0, PaddedVector* w0, const PaddedVector& x1,
                                PaddedVector* y1, PaddedVector* w1, double yw[2]) const;
  /// x = s + beta x (CG's new direction) over the free rows (x stays 0 elsewhere), then
  /// MultiplySplit(x, t, z, y). Never allocates.
  double UpdateMultiplySplit(const std::vector<Eigen::Matrix3d>& blocks, const std::vector<double>& scalars,
                             const PaddedVector& s, double beta, PaddedVector* x, PaddedVector* t, PaddedVector* z,
                             PaddedVector* y) const;
  /// CG's step over the free rows: y += alpha t, r -= alpha q (pads too), then s = D_w r as
  /// MultiplyDiagonal; returns r . s. With y_zero, y is taken as 0 (not read: y = 0 + alpha t).
  /// The other rows are skipped (y = +0 there with y_zero): CG keeps t, q, r, s and y +0 there
  /// (pads too), which updating them would leave as they are, so the results are those of
  /// updating all rows. A non-finite alpha (0 x alpha is NaN) updates all rows. Never allocates.
  double StepResidual(double alpha, const PaddedVector& t, const PaddedVector& q, bool y_zero, PaddedVector* y,
                      PaddedVector* r, PaddedVector* s) const;

  /// The sweeps use an AVX2 kernel where the CPU has it (checked at run time), else a portable
  /// one doing the same operations in the same order: identical results. This picks the
  /// portable one anyway (tests compare the two).
  void UsePortableKernel() { avx2_ = false; }
  /// Rows it was built for (0: default-constructed).
  int rows() const { return static_cast<int>(diag_slot_.size()); }
  bool uses_avx2() const { return avx2_; }

 private:
  std::vector<int> diag_slot_;      ///< per row: slot of its diagonal block
  std::vector<int> column_offset_;  ///< GaussSeidelSweepArgs::column_offset
  internal::GaussSeidelSweepArgs Args(const std::vector<Eigen::Matrix3d>& blocks,
                                      const std::vector<double>& scalars) const;

  std::vector<internal::SweepRowData> row_data_;  ///< per row
  bool avx2_ = false;
  double diag_excess_ = 0.0;  ///< (2 D_w - D) = diag_excess_ D_w: 2 - omega

  std::vector<unsigned char> row_free_;  ///< Update's: which rows are free
  std::vector<unsigned char> row_zero_;  ///< per row: its row_data_ blocks are all 0 (UpdateRows skips them)
  std::vector<int> runs_;                ///< Update's: the free rows' runs (GaussSeidelSweepArgs)
  int num_runs_ = 0;
  /// Update for the rows row_free_ marks (one pass, the kernel picked once).
  bool UpdateRows(const std::vector<Eigen::Matrix3d>& blocks, double omega);
};

template <typename RowFree>
bool GaussSeidelPreconditioner::Update(const std::vector<Eigen::Matrix3d>& blocks, double omega, RowFree row_free) {
  // Which rows are free, and their runs (a run starts where a free row follows one that is not).
  num_runs_ = 0;
  bool in_run = false;
  for (int r = 0; r < rows(); ++r) {
    const bool free = row_free(r);
    row_free_[static_cast<std::size_t>(r)] = free ? 1 : 0;
    if (free != in_run) {
      runs_[2 * static_cast<std::size_t>(num_runs_) + (free ? 0 : 1)] = r;
      num_runs_ += free ? 0 : 1;
      in_run = free;
    }
  }
  if (in_run) runs_[2 * static_cast<std::size_t>(num_runs_++) + 1] = rows();
  return UpdateRows(blocks, omega);
}

namespace internal {
/// One row's blocks for a free row with diagonal block a (gauss_seidel_preconditioner.cc):
/// d = a / omega, d_inv = its inverse, and d_inv b for the adjacent blocks b that are not null
/// (into lower, upper; left as they are for null b). Returns false if a is singular or the
/// results are not finite. `avx2` picks the 4-wide build: identical results.
bool SetRowBlocks(const Eigen::Matrix3d& a, double omega, const Eigen::Matrix3d* lower_block,
                  const Eigen::Matrix3d* upper_block, bool avx2, PaddedBlock* d, PaddedBlock* d_inv, PaddedBlock* lower,
                  PaddedBlock* upper);
}  // namespace internal

}  // namespace haptex::textile
