#include "libs/textile/block_pattern.h"

#include <algorithm>

#include "libs/textile/check.h"

namespace haptex::textile {

int BlockPattern::Slot(int r, int c) const {
  const auto begin = cols.begin() + row_start[static_cast<std::size_t>(r)];
  const auto end = cols.begin() + row_start[static_cast<std::size_t>(r) + 1];
  const auto it = std::lower_bound(begin, end, c);
  HAPTEX_TEXTILE_DEMAND(it != end && *it == c);
  return static_cast<int>(it - cols.begin());
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

}  // namespace haptex::textile
