#pragma once
// Fixed sparsity pattern of a symmetric block (3x3) matrix in CSR form, built once per model.

#include <utility>
#include <vector>

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

}  // namespace haptex::textile
