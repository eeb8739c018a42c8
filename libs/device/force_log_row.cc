#include "libs/device/force_log_row.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>

namespace haptex::device {

double ForceLogRow::CommandedNormN(int finger) const {
  const auto& f = commanded_D_N[static_cast<std::size_t>(finger)];
  return std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
}

std::size_t FormatForceLogRow(const ForceLogRow& row, std::span<char, kForceLogLineBytes> out) {
  // %g: six significant digits, what the force's float precision carries; positions to 1e-9 m, so
  // that differences of neighbouring rows (the motion in 0.2 ms) keep their digits
  const int n = std::snprintf(
      out.data(), out.size(), "%lld,%g,%g,%g,%g,%g,%g,%g,%g,%g,%g,%g,%g,%d,%u,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n",
      static_cast<long long>(row.time_ns), row.commanded_D_N[0][0], row.commanded_D_N[0][1], row.commanded_D_N[0][2],
      row.applied_D_N[0][0], row.applied_D_N[0][1], row.applied_D_N[0][2], row.commanded_D_N[1][0],
      row.commanded_D_N[1][1], row.commanded_D_N[1][2], row.applied_D_N[1][0], row.applied_D_N[1][1],
      row.applied_D_N[1][2], row.host_timed_out ? 1 : 0, static_cast<unsigned>(row.host_sequence),
      row.position_D_m[0][0], row.position_D_m[0][1], row.position_D_m[0][2], row.position_D_m[1][0],
      row.position_D_m[1][1], row.position_D_m[1][2]);
  return n > 0 ? std::min(static_cast<std::size_t>(n), out.size() - 1) : 0;
}

bool ParseForceLogRow(std::string_view line, ForceLogRow* row) {
  if (!line.empty() && line.back() == '\n') line.remove_suffix(1);
  std::array<double, kForceLogColumns> v{};
  std::size_t column = 0;
  const char* at = line.data();
  const char* end = line.data() + line.size();
  while (column < v.size()) {
    const auto [next, error] = std::from_chars(at, end, v[column]);
    if (error != std::errc() || !std::isfinite(v[column])) return false;
    ++column;
    at = next;
    if (at == end) break;
    if (*at != ',') return false;
    ++at;
  }
  if (column != v.size() || at != end) return false;
  row->time_ns = static_cast<std::int64_t>(v[0]);
  for (std::size_t f = 0; f < 2; ++f) {
    for (std::size_t k = 0; k < 3; ++k) {
      row->commanded_D_N[f][k] = v[1 + 6 * f + k];
      row->applied_D_N[f][k] = v[4 + 6 * f + k];
    }
  }
  row->host_timed_out = v[13] != 0;
  row->host_sequence = static_cast<std::uint32_t>(v[14]);
  for (std::size_t f = 0; f < 2; ++f) {
    for (std::size_t k = 0; k < 3; ++k) row->position_D_m[f][k] = v[15 + 3 * f + k];
  }
  return true;
}

}  // namespace haptex::device
