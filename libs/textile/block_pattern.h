#pragma once
// Fixed sparsity pattern of a symmetric block (3x3) matrix in CSR form, built once per model.

#include <utility>
#include <vector>

#include <Eigen/Core>

namespace haptex::textile {

/// Block-CSR pattern: row r holds blocks cols[row_start[r] .. row_start[r+1]).
struct BlockPattern {
  std::vector<int> row_start;  ///< size rows + 1
  std::vector<int> cols;       ///< column of each block (FromPairs: sorted within a row)
  std::vector<int> diag_slot;  ///< slot of block (r, r)

  int rows() const { return static_cast<int>(row_start.size()) - 1; }
  int num_blocks() const { return static_cast<int>(cols.size()); }
  /// Slot of block (r, c); aborts if the block is not in the pattern (a bug).
  int Slot(int r, int c) const;

  /// Moves the blocks with `to_end[slot]` to the end of their row (each group keeps its order),
  /// so that the other blocks of a row are contiguous. Slots change: call before recording any.
  void MoveToRowEnds(const std::vector<unsigned char>& to_end);

  /// Pattern with every diagonal block and both (i, j) and (j, i) for each coupled pair.
  static BlockPattern FromPairs(int rows, const std::vector<std::pair<int, int>>& pairs);
};

/// acc += sum over k in [k0, k1) of blocks[k] x_{cols[k]} (3x3 column-major blocks, written
/// out: Eigen's segment products compile to slower code here).
inline void AccumulateBlockRow(const Eigen::Matrix3d* blocks, const int* cols, int k0, int k1, const double* x,
                               double acc[3]) {
  double a0 = acc[0], a1 = acc[1], a2 = acc[2];
  for (int k = k0; k < k1; ++k) {
    const double* m = blocks[k].data();
    const double* xc = x + 3 * cols[k];
    const double x0 = xc[0], x1 = xc[1], x2 = xc[2];
    a0 += m[0] * x0 + m[3] * x1 + m[6] * x2;
    a1 += m[1] * x0 + m[4] * x1 + m[7] * x2;
    a2 += m[2] * x0 + m[5] * x1 + m[8] * x2;
  }
  acc[0] = a0;
  acc[1] = a1;
  acc[2] = a2;
}

/// y = A x for the rows r with row_active(r), zero in the other rows; `blocks` holds A's 3x3
/// blocks in `pattern`'s slot order. The product of the multigrid cycle (and of CG on
/// patterns without a split). Never allocates.
template <typename RowActive>
void MultiplyBlockRows(const BlockPattern& pattern, const std::vector<Eigen::Matrix3d>& blocks, RowActive row_active,
                       const Eigen::VectorXd& x, Eigen::VectorXd* y) {
  const int* row_start = pattern.row_start.data();
  const int* cols = pattern.cols.data();
  const int rows = pattern.rows();
  const double* xp = x.data();
  double* yp = y->data();
  for (int r = 0; r < rows; ++r) {
    double acc[3] = {0.0, 0.0, 0.0};
    if (row_active(r)) {
      AccumulateBlockRow(blocks.data(), cols, row_start[r], row_start[r + 1], xp, acc);
    }
    yp[3 * r] = acc[0];
    yp[3 * r + 1] = acc[1];
    yp[3 * r + 2] = acc[2];
  }
}

/// A pattern's rows split for the product: the general 3x3 blocks, and the blocks known to be a
/// scalar times the identity (for the fabric: the couplings only bending makes, two particles
/// apart on a grid line; constant per model and step). The scalar blocks cost one multiply-add
/// per component instead of three, and their 72 bytes are read as 8.
struct SplitRows {
  std::vector<int> general_start, general_col;             ///< rows + 1; per general block
  std::vector<int> general_first_slot;                     ///< per row: slot of its first general block
  std::vector<int> scalar_start, scalar_slot, scalar_col;  ///< rows + 1; per scalar block

  /// `is_scalar[slot]` marks the scalar blocks (never a diagonal one). A row's general blocks
  /// must be contiguous (BlockPattern::MoveToRowEnds(is_scalar)), so the product reads them in
  /// sequence.
  static SplitRows FromPattern(const BlockPattern& pattern, const std::vector<unsigned char>& is_scalar);
};

namespace internal {
/// The split product over rows [r0, r1), all active: y_r = (A x)_r; returns the sum of
/// x_r . y_r over them. A row's general blocks are summed column by column (column j times x_j),
/// even and odd blocks apart: six independent chains of adds, combined at the end of the row.
/// On CPUs with AVX (checked at run time) each block column is one 4-wide multiply and add;
/// elsewhere the same sums in the same order, so both give identical results. Never allocates.
double MultiplySplitRowRange(const SplitRows& split, const Eigen::Matrix3d* blocks, const double* scalars,
                             const double* x, double* y, int r0, int r1);
/// The same with the kernel picked: the AVX one if `avx` (only where base::CpuHasAvx()),
/// else the portable one (tests compare their bits).
double MultiplySplitRowRange(const SplitRows& split, const Eigen::Matrix3d* blocks, const double* scalars,
                             const double* x, double* y, int r0, int r1, bool avx);
}  // namespace internal

/// y = A x for the rows r with row_active(r), zero in the other rows, with A's general blocks
/// in `blocks` (slot order) and `scalars[k]` the value of scalar block k (split's order, e.g.
/// blocks[scalar_slot[k]](0, 0)). Same result as MultiplyBlockRows up to rounding; returns
/// x . y (CG's c'Ac, in the same pass). Never allocates.
template <typename RowActive>
double MultiplySplitRows(const SplitRows& split, const std::vector<Eigen::Matrix3d>& blocks,
                         const std::vector<double>& scalars, RowActive row_active, const Eigen::VectorXd& x,
                         Eigen::VectorXd* y) {
  const double* xp = x.data();
  double* yp = y->data();
  const int rows = static_cast<int>(split.general_start.size()) - 1;
  double xy = 0.0;
  int r = 0;
  while (r < rows) {
    if (!row_active(r)) {
      yp[3 * r] = 0.0;
      yp[3 * r + 1] = 0.0;
      yp[3 * r + 2] = 0.0;
      ++r;
      continue;
    }
    int r1 = r + 1;  // a run of active rows: one kernel call
    while (r1 < rows && row_active(r1)) ++r1;
    xy += internal::MultiplySplitRowRange(split, blocks.data(), scalars.data(), xp, yp, r, r1);
    r = r1;
  }
  return xy;
}

}  // namespace haptex::textile
