#include "libs/codec/cloth_positions.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace haptex::codec {

void EncodeClothPositions(const double* x_W_m, int count, double quantum_m, v1::ClothFrame* out) {
  out->set_quantum_m(quantum_m);
  auto* q = out->mutable_position_q();
  q->Clear();
  std::int64_t before[3] = {0, 0, 0};
  for (int p = 0; p < count; ++p) {
    for (int k = 0; k < 3; ++k) {
      const double steps = x_W_m[3 * p + k] / quantum_m;
      const std::int64_t now =
          std::isfinite(steps)
              ? static_cast<std::int64_t>(std::llround(std::clamp(steps, -static_cast<double>(kClothQuantisedLimit),
                                                                  static_cast<double>(kClothQuantisedLimit))))
              : before[k];
      q->Add(static_cast<std::int32_t>(now - before[k]));
      before[k] = now;
    }
  }
}

long DecodeClothPositions(const v1::ClothFrame& chunk, float* out_W_m, std::size_t capacity) {
  const double quantum_m = chunk.quantum_m();
  const auto n = static_cast<std::size_t>(chunk.position_q_size());
  if (!(std::isfinite(quantum_m) && quantum_m > 0.0) || n % 3 != 0 || n > capacity) return -1;
  if (n > 0 && !std::isfinite(static_cast<float>(quantum_m * kClothQuantisedLimit))) return -1;
  // checked whole before anything is written: a malformed chunk leaves `out_W_m` as it was
  std::int64_t sum[3] = {0, 0, 0};
  for (std::size_t i = 0; i < n; ++i) {
    std::int64_t& s = sum[i % 3];
    s += chunk.position_q(static_cast<int>(i));
    if (s > kClothQuantisedLimit || s < -static_cast<std::int64_t>(kClothQuantisedLimit)) return -1;
  }
  sum[0] = sum[1] = sum[2] = 0;
  for (std::size_t i = 0; i < n; ++i) {
    std::int64_t& s = sum[i % 3];
    s += chunk.position_q(static_cast<int>(i));
    out_W_m[i] = static_cast<float>(quantum_m * static_cast<double>(s));
  }
  return static_cast<long>(n);
}

}  // namespace haptex::codec
