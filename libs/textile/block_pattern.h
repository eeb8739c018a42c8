#pragma once
// Fixed sparsity pattern of a symmetric block (3x3) matrix in CSR form, built once per model.

#include <utility>
#include <vector>

#include <Eigen/Core>

namespace haptex::textile {

/// Block-CSR pattern: row r holds blocks cols[row_start[r] .. row_start[r+1]).
struct BlockPattern {
  std::vector<int> row_start;  ///< size rows + 1
  std::vector<int> cols;       ///< column of each block, sorted within a row
  std::vector<int> diag_slot;  ///< slot of block (r, r)

  int rows() const { return static_cast<int>(row_start.size()) - 1; }
  int num_blocks() const { return static_cast<int>(cols.size()); }
  /// Slot of block (r, c); aborts if the block is not in the pattern (a bug).
  int Slot(int r, int c) const;

  /// Pattern with every diagonal block and both (i, j) and (j, i) for each coupled pair.
  static BlockPattern FromPairs(int rows, const std::vector<std::pair<int, int>>& pairs);
};

/// y = A x for the rows r with row_active(r), zero in the other rows; `blocks` holds A's 3x3
/// blocks in `pattern`'s slot order. The hot product of CG and the multigrid cycle. Never
/// allocates.
template <typename RowActive>
void MultiplyBlockRows(const BlockPattern& pattern, const std::vector<Eigen::Matrix3d>& blocks,
                       RowActive row_active, const Eigen::VectorXd& x, Eigen::VectorXd* y) {
  const int* row_start = pattern.row_start.data();
  const int* cols = pattern.cols.data();
  const int rows = pattern.rows();
  for (int r = 0; r < rows; ++r) {
    Eigen::Vector3d acc = Eigen::Vector3d::Zero();
    if (row_active(r)) {
      for (int k = row_start[r]; k < row_start[r + 1]; ++k) {
        acc.noalias() += blocks[static_cast<std::size_t>(k)] * x.segment<3>(3 * cols[k]);
      }
    }
    y->segment<3>(3 * r) = acc;
  }
}

}  // namespace haptex::textile
