#include "launch/force_log_reader.h"

#include <fstream>
#include <iterator>
#include <string_view>

namespace haptex::launch {

std::vector<device::ForceLogRow> ForceLogTail::Next() {
  std::vector<device::ForceLogRow> rows;
  std::ifstream in(path_, std::ios::binary);
  if (!in) return rows;
  in.seekg(static_cast<std::streamoff>(offset_));
  const std::string chunk((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::size_t start = 0;
  device::ForceLogRow row;
  for (std::size_t end = chunk.find('\n'); end != std::string::npos; end = chunk.find('\n', start)) {
    if (device::ParseForceLogRow(std::string_view(chunk).substr(start, end - start), &row)) rows.push_back(row);
    start = end + 1;
  }
  offset_ += start;
  return rows;
}

std::vector<device::ForceLogRow> ReadForceLogRows(const std::string& path) { return ForceLogTail(path).Next(); }

}  // namespace haptex::launch
