#pragma once
// A small seeded generator whose sequence is the same on every platform and standard library
// (std::uniform_real_distribution is not), so mock runs replay bit for bit.

#include <cstdint>

namespace haptex::device {

/// SplitMix64 sequence; Uniform() maps the top 53 bits to [-1, 1).
class DeterministicRng {
 public:
  explicit DeterministicRng(std::uint64_t seed) : state_(seed) {}

  std::uint64_t Next() {
    state_ += 0x9E3779B97F4A7C15ull;
    std::uint64_t z = state_;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }

  /// Uniform in [-1, 1).
  double Uniform() { return static_cast<double>(Next() >> 11) * 0x1.0p-52 - 1.0; }

 private:
  std::uint64_t state_;
};

}  // namespace haptex::device
