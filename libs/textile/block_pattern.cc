#include "libs/textile/block_pattern.h"

#include <algorithm>
#include <utility>

#include "libs/textile/check.h"

namespace haptex::textile {

int BlockPattern::Slot(int r, int c) const {
  // Linear: rows are short, and MoveToRowEnds leaves them in two sorted groups.
  const auto begin = cols.begin() + row_start[static_cast<std::size_t>(r)];
  const auto end = cols.begin() + row_start[static_cast<std::size_t>(r) + 1];
  const auto it = std::find(begin, end, c);
  HAPTEX_TEXTILE_DEMAND(it != end);
  return static_cast<int>(it - cols.begin());
}

void BlockPattern::MoveToRowEnds(const std::vector<unsigned char>& to_end) {
  HAPTEX_TEXTILE_DEMAND(to_end.size() == cols.size());
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
    HAPTEX_TEXTILE_DEMAND(i >= 0 && i < rows && j >= 0 && j < rows);
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

SplitRows SplitRows::FromPattern(const BlockPattern& pattern,
                                 const std::vector<unsigned char>& is_scalar) {
  HAPTEX_TEXTILE_DEMAND(is_scalar.size() == pattern.cols.size());
  SplitRows s;
  s.general_start.push_back(0);
  s.general_first_slot.assign(static_cast<std::size_t>(pattern.rows()), 0);
  s.scalar_start.push_back(0);
  for (int r = 0; r < pattern.rows(); ++r) {
    for (int k = pattern.row_start[static_cast<std::size_t>(r)];
         k < pattern.row_start[static_cast<std::size_t>(r) + 1]; ++k) {
      const int c = pattern.cols[static_cast<std::size_t>(k)];
      if (is_scalar[static_cast<std::size_t>(k)]) {
        HAPTEX_TEXTILE_DEMAND(c != r);
        s.scalar_slot.push_back(k);
        s.scalar_col.push_back(c);
      } else {
        const int g = static_cast<int>(s.general_col.size()) - s.general_start.back();
        if (g == 0) s.general_first_slot[static_cast<std::size_t>(r)] = k;
        HAPTEX_TEXTILE_DEMAND(k == s.general_first_slot[static_cast<std::size_t>(r)] + g);  // contiguous
        s.general_col.push_back(c);
      }
    }
    s.general_start.push_back(static_cast<int>(s.general_col.size()));
    s.scalar_start.push_back(static_cast<int>(s.scalar_slot.size()));
  }
  return s;
}

}  // namespace haptex::textile
