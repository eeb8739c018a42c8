#include "libs/tactile/spectrum.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

#include "libs/tactile/fft.h"

namespace haptex::tactile {

PowerSpectrum ComputePowerSpectrum(const HeightMap& map) {
  const int nx = map.size_x(), ny = map.size_y();
  const auto px = static_cast<Eigen::Index>(NextPowerOfTwo(static_cast<std::size_t>(nx)));
  const auto py = static_cast<Eigen::Index>(NextPowerOfTwo(static_cast<std::size_t>(ny)));
  ComplexGrid grid = ComplexGrid::Zero(px, py);
  const double mean = map.MeanUm();
  double window_energy = 0.0;
  for (int iy = 0; iy < ny; ++iy) {
    const double wy = 0.5 - 0.5 * std::cos(2.0 * std::numbers::pi * (iy + 0.5) / ny);
    for (int ix = 0; ix < nx; ++ix) {
      const double w = wy * (0.5 - 0.5 * std::cos(2.0 * std::numbers::pi * (ix + 0.5) / nx));
      grid(ix, iy) = w * (map.height_um()(ix, iy) - mean);
      window_energy += w * w;
    }
  }
  Dft2d(&grid, false);
  PowerSpectrum out;
  out.power_um2 = grid.abs2() / (window_energy * static_cast<double>(px * py));
  out.df_x_per_m = 1.0 / (static_cast<double>(px) * map.pixel_size_m());
  out.df_y_per_m = 1.0 / (static_cast<double>(py) * map.pixel_size_m());
  return out;
}

std::vector<Eigen::Vector2d> DominantFrequencies(const PowerSpectrum& spectrum, int count) {
  const auto& p = spectrum.power_um2;
  const int nx = static_cast<int>(p.rows()), ny = static_cast<int>(p.cols());
  auto at = [&](int x, int y) { return p(((x % nx) + nx) % nx, ((y % ny) + ny) % ny); };
  std::vector<std::pair<double, Eigen::Vector2d>> peaks;
  for (int ky = -ny / 2 + 1; ky < ny / 2; ++ky) {
    for (int kx = 0; kx < nx / 2; ++kx) {
      if (kx == 0 && ky <= 0) continue;  // DC and the mirrored half
      const double v = at(kx, ky);
      bool is_max = v > 0.0;
      for (int dy = -1; dy <= 1 && is_max; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          if ((dx || dy) && at(kx + dx, ky + dy) > v) {
            is_max = false;
            break;
          }
        }
      }
      if (is_max) peaks.emplace_back(v, Eigen::Vector2d(kx * spectrum.df_x_per_m, ky * spectrum.df_y_per_m));
    }
  }
  std::sort(peaks.begin(), peaks.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  std::vector<Eigen::Vector2d> out;
  for (int i = 0; i < count && i < static_cast<int>(peaks.size()); ++i)
    out.push_back(peaks[static_cast<std::size_t>(i)].second);
  return out;
}

Eigen::ArrayXXd SpectrumImage(const PowerSpectrum& spectrum) {
  const auto& p = spectrum.power_um2;
  const Eigen::Index nx = p.rows(), ny = p.cols();
  const double floor = std::max(p.maxCoeff() * 1e-9, 1e-300);
  Eigen::ArrayXXd image(nx, ny);
  for (Eigen::Index y = 0; y < ny; ++y) {
    for (Eigen::Index x = 0; x < nx; ++x) {
      image((x + nx / 2) % nx, (y + ny / 2) % ny) = std::log10(std::max(p(x, y), floor));
    }
  }
  return image;
}

}  // namespace haptex::tactile
