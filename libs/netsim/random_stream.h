#pragma once
// One seeded stream of draws per kind of decision (loss, burst, jitter, ...), so that turning one
// knob leaves the draws of the others, and so their decisions, unchanged. Built on the
// project's platform-independent generator, never on a global or std:: distribution.

#include <cmath>
#include <cstdint>

#include "libs/device/deterministic_rng.h"

namespace haptex::netsim {

class RandomStream final {
 public:
  /// `stream` tells apart the streams of one seed.
  RandomStream(std::uint64_t seed, std::uint64_t stream) : rng_(Mix(seed, stream)) {}

  /// Uniform in [0, 1), 53 bits.
  double Uniform01() { return static_cast<double>(rng_.Next() >> 11) * 0x1.0p-53; }

  /// Standard normal (Marsaglia's polar method; the second value of each pair is kept).
  double StandardNormal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    double u = 0.0, v = 0.0, s = 0.0;
    do {
      u = 2.0 * Uniform01() - 1.0;
      v = 2.0 * Uniform01() - 1.0;
      s = u * u + v * v;
    } while (s >= 1.0 || s == 0.0);
    const double scale = std::sqrt(-2.0 * std::log(s) / s);
    spare_ = v * scale;
    has_spare_ = true;
    return u * scale;
  }

 private:
  // Streams start at hashed, unrelated points of the generator's sequence rather than at seeds
  // one step apart, which would be the same sequence shifted.
  static std::uint64_t Mix(std::uint64_t seed, std::uint64_t stream) {
    device::DeterministicRng mixer(seed ^ (stream * 0xD1B54A32D192ED03ull));
    mixer.Next();
    return mixer.Next();
  }

  device::DeterministicRng rng_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

}  // namespace haptex::netsim
