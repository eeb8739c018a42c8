#pragma once
// The virtual tactile fabric as the real-time side sees it: one lattice cell of heights (the mean
// tile) repeated over the fabric, plus an optional small periodic residual-noise patch.

#include <cmath>
#include <cstddef>
#include <iosfwd>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace haptex::tactile {

/// Periodic height field h(p) for p in fabric coordinates (u, v) [m].
/// Cell coordinates (s, t) = frac(B^-1 (p - origin)) with B = [a b]; the tile holds
/// samples_s x samples_t samples at (s, t) = (is / samples_s, it / samples_t), looked up bilinearly with
/// wrap-around (seamless by construction). The noise patch, if any, is an axis-aligned periodic
/// square of noise_size x noise_size samples spaced noise_pixel_m, added to the tile height.
class PeriodicTile final {
 public:
  /// @param basis_m columns a, b [m]; must be non-degenerate.
  /// @param heights_um samples_s x samples_t mean-tile heights [um]; at least 2 x 2, finite.
  /// @throws std::invalid_argument on a degenerate basis or bad heights.
  PeriodicTile(const Eigen::Matrix2d& basis_m, const Eigen::Vector2d& origin_m, const Eigen::ArrayXXd& heights_um);

  /// Adds a periodic residual-noise patch (square, side a power of two).
  /// @throws std::invalid_argument on a bad size or pixel.
  void SetNoise(const Eigen::ArrayXXd& noise_um, double noise_pixel_m);
  void SetStatistics(double residual_rms_um, double periodicity_index);

  const Eigen::Matrix2d& basis_m() const { return basis_m_; }
  const Eigen::Vector2d& origin_m() const { return origin_m_; }
  int samples_s() const { return samples_s_; }
  int samples_t() const { return samples_t_; }
  /// Mean-tile heights [um], index (is, it).
  Eigen::ArrayXXd TileHeightsUm() const;
  bool has_noise() const { return noise_size_ > 0; }
  int noise_size() const { return noise_size_; }
  double noise_pixel_m() const { return noise_pixel_m_; }
  Eigen::ArrayXXd NoiseUm() const;
  /// RMS of (original map - periodic tile) found by the analysis [um].
  double residual_rms_um() const { return residual_rms_um_; }
  /// 1 - var(residual) / var(map): 1 for a perfectly periodic map.
  double periodicity_index() const { return periodicity_index_; }

  /// Height at fabric position (u_m, v_m) [um]: tile plus noise. Real-time safe.
  double HeightUm(double u_m, double v_m) const {
    const double du = u_m - origin_m_.x();
    const double dv = v_m - origin_m_.y();
    double h = Wrapped(tile_, samples_s_, samples_t_, (inverse_(0, 0) * du + inverse_(0, 1) * dv) * samples_s_,
                       (inverse_(1, 0) * du + inverse_(1, 1) * dv) * samples_t_);
    if (noise_size_ > 0) {
      h += Wrapped(noise_, noise_size_, noise_size_, u_m * noise_inv_pixel_, v_m * noise_inv_pixel_);
    }
    return h;
  }

  /// A copy low-pass filtered with a Gaussian of standard deviation sigma_m (the pin/skin
  /// footprint), exact for the periodic field (done in Fourier space on the lattice).
  PeriodicTile Smoothed(double sigma_m) const;

  /// Samples the field on a grid (index (ix, iy) at (ix, iy) * pixel_size_m) [um].
  Eigen::ArrayXXd Render(int size_x, int size_y, double pixel_size_m) const;

  /// Binary tile file (format in docs/tactile.md). @throws std::runtime_error on I/O errors.
  void Save(std::ostream& out) const;
  void SaveFile(const std::string& path) const;
  /// @throws std::runtime_error on a malformed, truncated or implausible file.
  static PeriodicTile Load(std::istream& in);
  static PeriodicTile LoadFile(const std::string& path);

 private:
  // Bilinear lookup with wrap-around in sample units.
  static double Wrapped(const std::vector<double>& data, int ns, int nt, double fs, double ft) {
    // Far outside any fabric (or NaN): no surface rather than an overflowing cast.
    if (!(std::abs(fs) < 1e9) || !(std::abs(ft) < 1e9)) return 0.0;
    const double s_floor = std::floor(fs);
    const double t_floor = std::floor(ft);
    const double ws = fs - s_floor;
    const double wt = ft - t_floor;
    int i0 = static_cast<int>(s_floor) % ns;
    int j0 = static_cast<int>(t_floor) % nt;
    if (i0 < 0) i0 += ns;
    if (j0 < 0) j0 += nt;
    const int i1 = i0 + 1 == ns ? 0 : i0 + 1;
    const int j1 = j0 + 1 == nt ? 0 : j0 + 1;
    const double* r0 = data.data() + static_cast<std::ptrdiff_t>(j0) * ns;
    const double* r1 = data.data() + static_cast<std::ptrdiff_t>(j1) * ns;
    const double a = r0[i0] + ws * (r0[i1] - r0[i0]);
    const double b = r1[i0] + ws * (r1[i1] - r1[i0]);
    return a + wt * (b - a);
  }

  Eigen::Matrix2d basis_m_;
  Eigen::Matrix2d inverse_;
  Eigen::Vector2d origin_m_;
  int samples_s_ = 0;
  int samples_t_ = 0;
  std::vector<double> tile_;  // index is + samples_s * it
  int noise_size_ = 0;
  double noise_pixel_m_ = 0.0;
  double noise_inv_pixel_ = 0.0;
  std::vector<double> noise_;  // index ix + noise_size * iy
  double residual_rms_um_ = 0.0;
  double periodicity_index_ = 1.0;
};

}  // namespace haptex::tactile
