#include "libs/tactile/weave_surface.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <random>
#include <stdexcept>
#include <utility>

namespace haptex::tactile {
namespace {

int PositiveMod(int a, int n) { return ((a % n) + n) % n; }

void Validate(const WeaveParams& p) {
  if (!(p.warp_pitch_m > 0.0) || !(p.weft_pitch_m > 0.0) || !(p.yarn_diameter_m > 0.0) || !(p.flattening > 0.0)) {
    throw std::invalid_argument("WeaveParams: pitches, yarn diameter and flattening must be > 0");
  }
  if (!(p.pixel_size_m > 0.0) || p.size_x < 2 || p.size_y < 2) {
    throw std::invalid_argument("WeaveParams: pixel_size_m must be > 0 and the map at least 2 x 2");
  }
  if (!(p.smd_um > 0.0) || p.hairiness_fraction < 0.0) {
    throw std::invalid_argument("WeaveParams: smd_um must be > 0 and hairiness_fraction >= 0");
  }
  if (p.pattern == WeavePattern::kTwill && (p.twill_over < 1 || p.twill_under < 1)) {
    throw std::invalid_argument("WeaveParams: twill_over and twill_under must be >= 1");
  }
  if (p.pattern == WeavePattern::kSatin && (p.satin_repeat < 3 || p.satin_step < 1 || p.satin_step >= p.satin_repeat ||
                                            std::gcd(p.satin_step, p.satin_repeat) != 1)) {
    throw std::invalid_argument("WeaveParams: satin needs repeat >= 3 and a step coprime with it");
  }
}

// Elliptical yarn cross-section of half-width w/2 and height d/2.
double CrossSection(double offset_m, double width_m, double diameter_m) {
  const double r = 2.0 * offset_m / width_m;
  return 0.5 * diameter_m * std::sqrt(std::max(0.0, 1.0 - r * r));
}

// Centreline height of a thread between two crossings: +c over, -c under, cosine-blended.
double Centreline(bool over_here, bool over_next, double fraction, double crimp_m) {
  const double z0 = over_here ? crimp_m : -crimp_m;
  const double z1 = over_next ? crimp_m : -crimp_m;
  const double w = 0.5 - 0.5 * std::cos(std::numbers::pi * fraction);
  return z0 + (z1 - z0) * w;
}

}  // namespace

bool WarpOver(const WeaveParams& p, int i, int j) {
  switch (p.pattern) {
    case WeavePattern::kPlain:
      return PositiveMod(i + j, 2) == 0;
    case WeavePattern::kTwill:
      return PositiveMod(i - j, p.twill_over + p.twill_under) < p.twill_over;
    case WeavePattern::kSatin:
      // Warp-faced: the weft floats over the warp at one interlacing per repeat.
      return PositiveMod(j - i * p.satin_step, p.satin_repeat) != 0;
  }
  return false;
}

HeightMap GenerateWeave(const WeaveParams& p) {
  Validate(p);
  const double width_m = p.yarn_diameter_m * p.flattening;
  const double crimp_m = 0.25 * p.yarn_diameter_m;
  Eigen::ArrayXXd h(p.size_x, p.size_y);
  for (int iy = 0; iy < p.size_y; ++iy) {
    const double y = iy * p.pixel_size_m;
    for (int ix = 0; ix < p.size_x; ++ix) {
      const double x = ix * p.pixel_size_m;
      // Thread cells: warp thread i is centred at x = (i + 0.5) * pitch, weft j at y = (j + 0.5) * pitch.
      const double cx = x / p.warp_pitch_m - 0.5;
      const double cy = y / p.weft_pitch_m - 0.5;
      const int i0 = static_cast<int>(std::floor(cx));
      const int j0 = static_cast<int>(std::floor(cy));
      double top = -1.0;
      // The nearest two warp threads (their flattened width may overlap the neighbour cell).
      for (int i = i0; i <= i0 + 1; ++i) {
        const double z = Centreline(WarpOver(p, i, j0), WarpOver(p, i, j0 + 1), cy - j0, crimp_m);
        top = std::max(top, z + CrossSection(x - (i + 0.5) * p.warp_pitch_m, width_m, p.yarn_diameter_m));
      }
      for (int j = j0; j <= j0 + 1; ++j) {
        const double z = Centreline(!WarpOver(p, i0, j), !WarpOver(p, i0 + 1, j), cx - i0, crimp_m);
        top = std::max(top, z + CrossSection(y - (j + 0.5) * p.weft_pitch_m, width_m, p.yarn_diameter_m));
      }
      h(ix, iy) = top * 1e6;
    }
  }
  if (p.hairiness_fraction > 0.0) {
    // Hairiness: box-smoothed white noise, added after a first scaling so its RMS is relative to the SMD.
    HeightMap base(h, p.pixel_size_m);
    const double mad = base.MeanAbsoluteDeviationUm();
    if (mad > 0.0) h = h.mean() + (h - h.mean()) * (p.smd_um / mad);
    std::mt19937_64 rng(p.seed);
    std::normal_distribution<double> normal(0.0, 1.0);
    Eigen::ArrayXXd noise(p.size_x, p.size_y);
    for (Eigen::Index k = 0; k < noise.size(); ++k) noise(k) = normal(rng);
    Eigen::ArrayXXd smooth = Eigen::ArrayXXd::Zero(p.size_x, p.size_y);
    for (int iy = 0; iy < p.size_y; ++iy) {
      for (int ix = 0; ix < p.size_x; ++ix) {
        double sum = 0.0;
        int n = 0;
        for (int dy = -1; dy <= 1; ++dy) {
          for (int dx = -1; dx <= 1; ++dx) {
            const int x = ix + dx, y = iy + dy;
            if (x < 0 || y < 0 || x >= p.size_x || y >= p.size_y) continue;
            sum += noise(x, y);
            ++n;
          }
        }
        smooth(ix, iy) = sum / n;
      }
    }
    const double rms = std::sqrt((smooth - smooth.mean()).square().mean());
    if (rms > 0.0) h += smooth * (p.hairiness_fraction * p.smd_um / rms);
  }
  HeightMap map(std::move(h), p.pixel_size_m);
  const double mad = map.MeanAbsoluteDeviationUm();
  if (mad > 0.0) map.ScaleDeviation(p.smd_um / mad);
  return map;
}

Eigen::Matrix2d WeaveLatticeBasis(const WeaveParams& p) {
  Validate(p);
  const double px = p.warp_pitch_m, py = p.weft_pitch_m;
  Eigen::Matrix2d b;
  switch (p.pattern) {
    case WeavePattern::kPlain:
      // (i+1, j+1) keeps i+j even: the cell is diagonal, half of 2 x 2 threads.
      b << px, px, py, -py;
      break;
    case WeavePattern::kTwill: {
      const int r = p.twill_over + p.twill_under;
      b << px, r * px, py, 0.0;
      break;
    }
    case WeavePattern::kSatin: {
      // (i+1, j+step) keeps j - i*step fixed; the repeat closes the lattice.
      const int r = p.satin_repeat;
      b << px, 0.0, p.satin_step * py, r * py;
      break;
    }
  }
  return b;
}

}  // namespace haptex::tactile
