#include "libs/tactile/periodicity.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

#include <Eigen/Dense>

#include "libs/tactile/fft.h"

namespace haptex::tactile {
namespace {

struct Peak {
  Eigen::Vector2d lag_px;
  double value;
};

double Cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

// Heights minus their least-squares plane.
Eigen::ArrayXXd Detrended(const HeightMap& map) {
  const int nx = map.size_x(), ny = map.size_y();
  Eigen::Matrix3d ata = Eigen::Matrix3d::Zero();
  Eigen::Vector3d atb = Eigen::Vector3d::Zero();
  for (int iy = 0; iy < ny; ++iy) {
    for (int ix = 0; ix < nx; ++ix) {
      const Eigen::Vector3d row(1.0, ix, iy);
      ata += row * row.transpose();
      atb += row * map.height_um()(ix, iy);
    }
  }
  const Eigen::Vector3d c = ata.ldlt().solve(atb);
  Eigen::ArrayXXd out(nx, ny);
  for (int iy = 0; iy < ny; ++iy) {
    for (int ix = 0; ix < nx; ++ix) out(ix, iy) = map.height_um()(ix, iy) - (c(0) + c(1) * ix + c(2) * iy);
  }
  return out;
}

// Parabola vertex offset through three samples, in (-0.5, 0.5).
double ParabolicOffset(double left, double centre, double right) {
  const double denom = left - 2.0 * centre + right;
  if (!(denom < 0.0)) return 0.0;
  return std::clamp(0.5 * (left - right) / denom, -0.5, 0.5);
}

Eigen::Matrix2d Oriented(Eigen::Matrix2d b) {
  if (b(0, 0) < 0.0 || (b(0, 0) == 0.0 && b(1, 0) < 0.0)) b.col(0) = -b.col(0);
  if (b.determinant() < 0.0) b.col(1) = -b.col(1);
  return b;
}

}  // namespace

Eigen::Matrix2d ReduceBasis(const Eigen::Matrix2d& basis) {
  Eigen::Vector2d a = basis.col(0), b = basis.col(1);
  if (a.squaredNorm() > b.squaredNorm()) std::swap(a, b);
  for (int iter = 0; iter < 64; ++iter) {
    const double mu = std::round(a.dot(b) / a.squaredNorm());
    b -= mu * a;
    if (b.squaredNorm() >= a.squaredNorm()) break;
    std::swap(a, b);
  }
  Eigen::Matrix2d out;
  out << a, b;
  return out;
}

double LatticeMismatch(const Eigen::Matrix2d& reference, const Eigen::Matrix2d& candidate) {
  const Eigen::Matrix2d m = reference.inverse() * candidate;
  const Eigen::Matrix2d rounded = m.array().round().matrix();
  if (std::abs(std::abs(rounded.determinant()) - 1.0) > 1e-9) return std::numeric_limits<double>::infinity();
  return (reference * rounded - candidate).colwise().norm().maxCoeff();
}

Eigen::ArrayXXd NormalisedAutocorrelation(const HeightMap& map, int max_lag_x, int max_lag_y) {
  const int nx = map.size_x(), ny = map.size_y();
  if (max_lag_x < 1 || max_lag_y < 1 || max_lag_x >= nx || max_lag_y >= ny) {
    throw std::invalid_argument("NormalisedAutocorrelation: lags must be in 1..size-1");
  }
  // Zero padding to at least size + lag keeps the circular correlation free of wrap-around.
  const auto px = static_cast<Eigen::Index>(NextPowerOfTwo(static_cast<std::size_t>(nx + max_lag_x)));
  const auto py = static_cast<Eigen::Index>(NextPowerOfTwo(static_cast<std::size_t>(ny + max_lag_y)));
  ComplexGrid grid = ComplexGrid::Zero(px, py);
  grid.topLeftCorner(nx, ny) = Detrended(map).cast<std::complex<double>>();
  Dft2d(&grid, false);
  grid = grid.abs2().cast<std::complex<double>>();
  Dft2d(&grid, true);
  Eigen::ArrayXXd r(2 * max_lag_x + 1, 2 * max_lag_y + 1);
  for (int dy = -max_lag_y; dy <= max_lag_y; ++dy) {
    for (int dx = -max_lag_x; dx <= max_lag_x; ++dx) {
      const double overlap = static_cast<double>(nx - std::abs(dx)) * (ny - std::abs(dy));
      r(dx + max_lag_x, dy + max_lag_y) = grid((dx + px) % px, (dy + py) % py).real() / overlap;
    }
  }
  const double r0 = r(max_lag_x, max_lag_y);
  if (!(r0 > 0.0)) throw std::runtime_error("NormalisedAutocorrelation: the map is flat");
  return r / r0;
}

LatticeEstimate EstimateLattice(const HeightMap& map, const PeriodicityOptions& options) {
  const int lx = std::max(2, static_cast<int>(options.max_lag_fraction * map.size_x()));
  const int ly = std::max(2, static_cast<int>(options.max_lag_fraction * map.size_y()));
  const Eigen::ArrayXXd r = NormalisedAutocorrelation(map, lx, ly);

  // Local maxima (5 x 5 neighbourhood) in the half plane dy > 0 or (dy == 0, dx > 0).
  std::vector<Peak> peaks;
  constexpr int kRadius = 2;
  for (int dy = 0; dy <= ly - kRadius; ++dy) {
    for (int dx = -lx + kRadius; dx <= lx - kRadius; ++dx) {
      if (dy == 0 && dx <= 0) continue;
      const int cx = dx + lx, cy = dy + ly;
      const double v = r(cx, cy);
      if (v < options.min_peak_correlation) continue;
      bool is_max = true;
      for (int oy = -kRadius; oy <= kRadius && is_max; ++oy) {
        for (int ox = -kRadius; ox <= kRadius; ++ox) {
          if ((ox || oy) && r(cx + ox, cy + oy) > v) {
            is_max = false;
            break;
          }
        }
      }
      if (!is_max) continue;
      const Eigen::Vector2d sub(ParabolicOffset(r(cx - 1, cy), v, r(cx + 1, cy)),
                                ParabolicOffset(r(cx, cy - 1), v, r(cx, cy + 1)));
      peaks.push_back({Eigen::Vector2d(dx, dy) + sub, v});
    }
  }
  double best = 0.0;
  for (const Peak& p : peaks) best = std::max(best, p.value);
  std::vector<Peak> candidates;
  for (const Peak& p : peaks) {
    if (p.value >= options.relative_peak_threshold * best) candidates.push_back(p);
  }
  std::sort(candidates.begin(), candidates.end(),
            [](const Peak& a, const Peak& b) { return a.lag_px.squaredNorm() < b.lag_px.squaredNorm(); });

  // Shortest peak, then the shortest one clearly not collinear with it.
  const Peak* a = candidates.empty() ? nullptr : &candidates.front();
  const Peak* b = nullptr;
  for (const Peak& p : candidates) {
    if (a && std::abs(Cross(a->lag_px, p.lag_px)) > 0.2 * a->lag_px.norm() * p.lag_px.norm()) {
      b = &p;
      break;
    }
  }
  if (!a || !b) {
    throw std::runtime_error(
        "EstimateLattice: no two independent autocorrelation peaks; the map is not periodic or covers "
        "fewer than two periods in some direction");
  }
  Eigen::Matrix2d basis;
  basis << a->lag_px, b->lag_px;
  basis = ReduceBasis(basis);

  // Least squares over every peak near a lattice point: B = (sum p n^T)(sum n n^T)^-1.
  int used = 0;
  for (int iter = 0; iter < 3; ++iter) {
    const Eigen::Matrix2d inverse = basis.inverse();
    const double tolerance = 0.15 * std::min(basis.col(0).norm(), basis.col(1).norm());
    Eigen::Matrix2d pn = Eigen::Matrix2d::Zero(), nn = Eigen::Matrix2d::Zero();
    used = 0;
    for (const Peak& p : candidates) {
      const Eigen::Vector2d n = (inverse * p.lag_px).array().round().matrix();
      if (n.isZero() || (basis * n - p.lag_px).norm() > tolerance) continue;
      pn += p.lag_px * n.transpose();
      nn += n * n.transpose();
      ++used;
    }
    if (std::abs(nn.determinant()) < 1e-9) break;
    basis = ReduceBasis(pn * nn.inverse());
  }
  LatticeEstimate out;
  out.peaks_used = used;
  out.peak_correlation = best;

  // Sub-lattices F [[a, b], [0, d]] (a d = n, 0 <= b < a) of the peak lattice F, scored by the
  // periodicity index of their mean tile; cells covering more than a quarter of the map are skipped.
  const Eigen::Matrix2d fine_m = basis * map.pixel_size_m();
  const double map_area = map.extent_x_m() * map.extent_y_m();
  struct Scored {
    Eigen::Matrix2d basis_m;
    int index;
    double periodicity;
  };
  std::vector<Scored> scored;
  PeriodicityOptions plain = options;
  plain.noise_size = 0;
  for (int n = 1; n <= std::max(1, options.max_sublattice_index); ++n) {
    for (int a_mul = 1; a_mul <= n; ++a_mul) {
      if (n % a_mul != 0) continue;
      const int d_mul = n / a_mul;
      for (int b_mul = 0; b_mul < a_mul; ++b_mul) {
        Eigen::Matrix2d hnf;
        hnf << a_mul, b_mul, 0.0, d_mul;
        const Eigen::Matrix2d candidate = Oriented(ReduceBasis(fine_m * hnf));
        if (std::abs(candidate.determinant()) > 0.25 * map_area) continue;
        try {
          scored.push_back({candidate, n, ExtractPeriodicTile(map, candidate, plain).periodicity_index()});
        } catch (const std::runtime_error&) {
          // Cell too large for this map: not a candidate.
        }
      }
    }
  }
  if (scored.empty()) throw std::runtime_error("EstimateLattice: the lattice cell is too large for the map");
  double best_periodicity = -std::numeric_limits<double>::infinity();
  for (const Scored& s : scored) best_periodicity = std::max(best_periodicity, s.periodicity);
  const Scored* chosen = nullptr;
  for (const Scored& s : scored) {
    if (s.periodicity < best_periodicity - options.sublattice_tolerance) continue;
    if (!chosen || s.index < chosen->index || (s.index == chosen->index && s.periodicity > chosen->periodicity)) {
      chosen = &s;
    }
  }
  out.basis_m = chosen->basis_m;
  out.sublattice_index = chosen->index;
  out.periodicity_index = chosen->periodicity;
  return out;
}

PeriodicTile ExtractPeriodicTile(const HeightMap& map, const Eigen::Matrix2d& basis_m,
                                 const PeriodicityOptions& options) {
  const double pixel = map.pixel_size_m();
  if (!(options.tile_oversampling > 0.0))
    throw std::invalid_argument("PeriodicityOptions: tile_oversampling must be > 0");
  const int ns = std::max(8, static_cast<int>(std::ceil(basis_m.col(0).norm() / pixel * options.tile_oversampling)));
  const int nt = std::max(8, static_cast<int>(std::ceil(basis_m.col(1).norm() / pixel * options.tile_oversampling)));
  if (ns > 4096 || nt > 4096) throw std::runtime_error("ExtractPeriodicTile: cell too large for the pixel size");
  const Eigen::Matrix2d inverse = basis_m.inverse();

  // Range of cell indices that can reach the map.
  const double ex = map.extent_x_m(), ey = map.extent_y_m();
  Eigen::Matrix<double, 2, 4> corners;
  corners << 0.0, ex, 0.0, ex, 0.0, 0.0, ey, ey;
  const Eigen::Matrix<double, 2, 4> cell = inverse * corners;
  const int n_lo = static_cast<int>(std::floor(cell.row(0).minCoeff())) - 1;
  const int n_hi = static_cast<int>(std::ceil(cell.row(0).maxCoeff())) + 1;
  const int m_lo = static_cast<int>(std::floor(cell.row(1).minCoeff())) - 1;
  const int m_hi = static_cast<int>(std::ceil(cell.row(1).maxCoeff())) + 1;

  // Mean over every cell copy of each tile sample that falls inside the map.
  Eigen::ArrayXXd tile(ns, nt);
  for (int it = 0; it < nt; ++it) {
    for (int is = 0; is < ns; ++is) {
      double sum = 0.0;
      int count = 0;
      for (int m = m_lo; m <= m_hi; ++m) {
        for (int n = n_lo; n <= n_hi; ++n) {
          const Eigen::Vector2d p =
              basis_m * Eigen::Vector2d(n + static_cast<double>(is) / ns, m + static_cast<double>(it) / nt);
          if (p.x() < 0.0 || p.y() < 0.0 || p.x() > ex || p.y() > ey) continue;
          sum += map.SampleUm(p.x(), p.y());
          ++count;
        }
      }
      if (count == 0) throw std::runtime_error("ExtractPeriodicTile: the map is smaller than one cell");
      tile(is, it) = sum / count;
    }
  }
  PeriodicTile out(basis_m, Eigen::Vector2d::Zero(), tile);

  // Residual statistics over the whole map.
  const int nx = map.size_x(), ny = map.size_y();
  const Eigen::ArrayXXd periodic = out.Render(nx, ny, pixel);
  const Eigen::ArrayXXd residual = map.height_um() - periodic;
  const double var_map = (map.height_um() - map.MeanUm()).square().mean();
  const double var_res = (residual - residual.mean()).square().mean();
  const double rms = std::sqrt(var_res);
  out.SetStatistics(rms, var_map > 0.0 ? 1.0 - var_res / var_map : 0.0);

  // Residual noise: the centre patch's amplitude spectrum with random phases (seeded), so the
  // noise is periodic on the patch and has the residual's spectrum and RMS.
  const int n = options.noise_size;
  if (n > 0) {
    if ((n & (n - 1)) != 0 || n > nx || n > ny) {
      throw std::invalid_argument("PeriodicityOptions: noise_size must be a power of two no larger than the map");
    }
    ComplexGrid patch = residual.block((nx - n) / 2, (ny - n) / 2, n, n).cast<std::complex<double>>();
    patch -= patch.mean();
    Dft2d(&patch, false);
    std::mt19937_64 rng(options.seed);
    std::normal_distribution<double> normal(0.0, 1.0);
    ComplexGrid white(n, n);
    for (Eigen::Index k = 0; k < white.size(); ++k) white(k) = normal(rng);
    Dft2d(&white, false);
    for (Eigen::Index k = 0; k < white.size(); ++k) {
      const double mag = std::abs(white(k));
      white(k) = mag > 0.0 ? white(k) / mag * std::abs(patch(k)) : 0.0;
    }
    white(0) = 0.0;
    Dft2d(&white, true);
    Eigen::ArrayXXd noise = white.real();
    const double noise_rms = std::sqrt((noise - noise.mean()).square().mean());
    if (noise_rms > 0.0) noise = (noise - noise.mean()) * (rms / noise_rms);
    out.SetNoise(noise, pixel);
  }
  return out;
}

PeriodicTile AnalysePeriodicity(const HeightMap& map, const PeriodicityOptions& options) {
  return ExtractPeriodicTile(map, EstimateLattice(map, options).basis_m, options);
}

}  // namespace haptex::tactile
