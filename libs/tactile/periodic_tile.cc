#include "libs/tactile/periodic_tile.h"

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <istream>
#include <numbers>
#include <ostream>
#include <stdexcept>

#include <Eigen/LU>

#include "libs/tactile/fft.h"

namespace haptex::tactile {
namespace {

constexpr char kMagic[8] = {'H', 'P', 'T', 'X', 'T', 'I', 'L', 'E'};
constexpr std::uint32_t kVersion = 1;
constexpr int kMaxSamples = 4096;

// Little-endian primitives, byte by byte so the format does not depend on the host.
void PutU32(std::ostream& out, std::uint32_t v) {
  unsigned char b[4];
  for (int i = 0; i < 4; ++i) b[i] = static_cast<unsigned char>(v >> (8 * i));
  out.write(reinterpret_cast<const char*>(b), 4);
}
void PutF64(std::ostream& out, double v) {
  const auto bits = std::bit_cast<std::uint64_t>(v);
  unsigned char b[8];
  for (int i = 0; i < 8; ++i) b[i] = static_cast<unsigned char>(bits >> (8 * i));
  out.write(reinterpret_cast<const char*>(b), 8);
}
void PutF32(std::ostream& out, float v) { PutU32(out, std::bit_cast<std::uint32_t>(v)); }

void ReadBytes(std::istream& in, unsigned char* b, std::streamsize n) {
  in.read(reinterpret_cast<char*>(b), n);
  if (in.gcount() != n) throw std::runtime_error("tile file: truncated");
}
std::uint32_t GetU32(std::istream& in) {
  unsigned char b[4];
  ReadBytes(in, b, 4);
  std::uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v |= static_cast<std::uint32_t>(b[i]) << (8 * i);
  return v;
}
double GetF64(std::istream& in) {
  unsigned char b[8];
  ReadBytes(in, b, 8);
  std::uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v |= static_cast<std::uint64_t>(b[i]) << (8 * i);
  const double d = std::bit_cast<double>(v);
  if (!std::isfinite(d)) throw std::runtime_error("tile file: non-finite value");
  return d;
}
float GetF32(std::istream& in) {
  const float f = std::bit_cast<float>(GetU32(in));
  if (!std::isfinite(f)) throw std::runtime_error("tile file: non-finite height");
  return f;
}

int SignedBin(int k, int n) { return k <= n / 2 ? k : k - n; }

// Gaussian low-pass of a periodic grid; freq(k, l) gives the spatial frequency [cycles/m].
template <typename FrequencyOf>
Eigen::ArrayXXd GaussianLowPass(const Eigen::ArrayXXd& values, double sigma_m, FrequencyOf freq) {
  ComplexGrid grid = values.cast<std::complex<double>>();
  Dft2d(&grid, false);
  const int ns = static_cast<int>(values.rows()), nt = static_cast<int>(values.cols());
  const double c = -2.0 * std::numbers::pi * std::numbers::pi * sigma_m * sigma_m;
  for (int l = 0; l < nt; ++l) {
    for (int k = 0; k < ns; ++k) {
      const Eigen::Vector2d q = freq(SignedBin(k, ns), SignedBin(l, nt));
      grid(k, l) *= std::exp(c * q.squaredNorm());
    }
  }
  Dft2d(&grid, true);
  return grid.real();
}

}  // namespace

PeriodicTile::PeriodicTile(const Eigen::Matrix2d& basis_m, const Eigen::Vector2d& origin_m,
                           const Eigen::ArrayXXd& heights_um)
    : basis_m_(basis_m), origin_m_(origin_m) {
  const double det = basis_m.determinant();
  const double scale = basis_m.col(0).norm() * basis_m.col(1).norm();
  if (!basis_m.allFinite() || !(std::abs(det) > 1e-6 * scale) || !(scale > 0.0)) {
    throw std::invalid_argument("PeriodicTile: lattice basis is degenerate or not finite");
  }
  if (!origin_m.allFinite()) throw std::invalid_argument("PeriodicTile: origin must be finite");
  if (heights_um.rows() < 2 || heights_um.cols() < 2 || heights_um.rows() > kMaxSamples ||
      heights_um.cols() > kMaxSamples || !heights_um.allFinite()) {
    throw std::invalid_argument("PeriodicTile: heights must be finite, 2..4096 samples per side");
  }
  inverse_ = basis_m.inverse();
  samples_s_ = static_cast<int>(heights_um.rows());
  samples_t_ = static_cast<int>(heights_um.cols());
  tile_.resize(static_cast<std::size_t>(heights_um.size()));
  for (int it = 0; it < samples_t_; ++it) {
    for (int is = 0; is < samples_s_; ++is) {
      tile_[static_cast<std::size_t>(is + samples_s_ * it)] = heights_um(is, it);
    }
  }
}

void PeriodicTile::SetNoise(const Eigen::ArrayXXd& noise_um, double noise_pixel_m) {
  const auto n = noise_um.rows();
  if (n != noise_um.cols() || n < 2 || n > kMaxSamples || (n & (n - 1)) != 0) {
    throw std::invalid_argument("PeriodicTile: noise patch must be square with a power-of-two side");
  }
  if (!(noise_pixel_m > 0.0) || !std::isfinite(noise_pixel_m) || !noise_um.allFinite()) {
    throw std::invalid_argument("PeriodicTile: noise pixel must be > 0 and noise finite");
  }
  noise_size_ = static_cast<int>(n);
  noise_pixel_m_ = noise_pixel_m;
  noise_inv_pixel_ = 1.0 / noise_pixel_m;
  noise_.resize(static_cast<std::size_t>(n * n));
  for (Eigen::Index y = 0; y < n; ++y) {
    for (Eigen::Index x = 0; x < n; ++x) noise_[static_cast<std::size_t>(x + n * y)] = noise_um(x, y);
  }
}

void PeriodicTile::SetStatistics(double residual_rms_um, double periodicity_index) {
  residual_rms_um_ = residual_rms_um;
  periodicity_index_ = periodicity_index;
}

Eigen::ArrayXXd PeriodicTile::TileHeightsUm() const {
  Eigen::ArrayXXd h(samples_s_, samples_t_);
  for (int it = 0; it < samples_t_; ++it) {
    for (int is = 0; is < samples_s_; ++is) h(is, it) = tile_[static_cast<std::size_t>(is + samples_s_ * it)];
  }
  return h;
}

Eigen::ArrayXXd PeriodicTile::NoiseUm() const {
  Eigen::ArrayXXd h(noise_size_, noise_size_);
  for (int y = 0; y < noise_size_; ++y) {
    for (int x = 0; x < noise_size_; ++x) h(x, y) = noise_[static_cast<std::size_t>(x + noise_size_ * y)];
  }
  return h;
}

PeriodicTile PeriodicTile::Smoothed(double sigma_m) const {
  if (!(sigma_m >= 0.0) || !std::isfinite(sigma_m)) {
    throw std::invalid_argument("PeriodicTile::Smoothed: sigma_m must be finite and >= 0");
  }
  if (sigma_m == 0.0) return *this;
  // Cell harmonic (k, l) has spatial frequency B^-T (k, l) [cycles/m].
  const Eigen::Matrix2d reciprocal = inverse_.transpose();
  PeriodicTile out(basis_m_, origin_m_, GaussianLowPass(TileHeightsUm(), sigma_m, [&](int k, int l) {
                     return Eigen::Vector2d(reciprocal * Eigen::Vector2d(k, l));
                   }));
  if (has_noise()) {
    const double df = 1.0 / (noise_size_ * noise_pixel_m_);
    out.SetNoise(GaussianLowPass(NoiseUm(), sigma_m, [&](int k, int l) { return Eigen::Vector2d(k * df, l * df); }),
                 noise_pixel_m_);
  }
  out.SetStatistics(residual_rms_um_, periodicity_index_);
  return out;
}

Eigen::ArrayXXd PeriodicTile::Render(int size_x, int size_y, double pixel_size_m) const {
  Eigen::ArrayXXd h(size_x, size_y);
  for (int iy = 0; iy < size_y; ++iy) {
    for (int ix = 0; ix < size_x; ++ix) h(ix, iy) = HeightUm(ix * pixel_size_m, iy * pixel_size_m);
  }
  return h;
}

void PeriodicTile::Save(std::ostream& out) const {
  out.write(kMagic, 8);
  PutU32(out, kVersion);
  PutU32(out, static_cast<std::uint32_t>(samples_s_));
  PutU32(out, static_cast<std::uint32_t>(samples_t_));
  PutU32(out, static_cast<std::uint32_t>(noise_size_));
  PutF64(out, basis_m_(0, 0));
  PutF64(out, basis_m_(1, 0));
  PutF64(out, basis_m_(0, 1));
  PutF64(out, basis_m_(1, 1));
  PutF64(out, origin_m_.x());
  PutF64(out, origin_m_.y());
  PutF64(out, residual_rms_um_);
  PutF64(out, periodicity_index_);
  PutF64(out, noise_pixel_m_);
  for (double h : tile_) PutF32(out, static_cast<float>(h));
  for (double h : noise_) PutF32(out, static_cast<float>(h));
  if (!out) throw std::runtime_error("tile file: write failed");
}

void PeriodicTile::SaveFile(const std::string& path) const {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw std::runtime_error("tile file: cannot create " + path);
  Save(out);
}

PeriodicTile PeriodicTile::Load(std::istream& in) {
  char magic[8];
  in.read(magic, 8);
  if (in.gcount() != 8 || std::memcmp(magic, kMagic, 8) != 0) throw std::runtime_error("tile file: bad magic");
  if (GetU32(in) != kVersion) throw std::runtime_error("tile file: unsupported version");
  const std::uint32_t ns = GetU32(in), nt = GetU32(in), nn = GetU32(in);
  if (ns < 2 || nt < 2 || ns > kMaxSamples || nt > kMaxSamples || nn > kMaxSamples || nn == 1) {
    throw std::runtime_error("tile file: implausible sample counts");
  }
  Eigen::Matrix2d basis;
  basis(0, 0) = GetF64(in);
  basis(1, 0) = GetF64(in);
  basis(0, 1) = GetF64(in);
  basis(1, 1) = GetF64(in);
  Eigen::Vector2d origin;
  origin.x() = GetF64(in);
  origin.y() = GetF64(in);
  const double residual = GetF64(in), index = GetF64(in), noise_pixel = GetF64(in);
  Eigen::ArrayXXd heights(ns, nt);
  for (std::uint32_t it = 0; it < nt; ++it) {
    for (std::uint32_t is = 0; is < ns; ++is) heights(is, it) = GetF32(in);
  }
  try {
    PeriodicTile tile(basis, origin, heights);
    if (nn > 0) {
      Eigen::ArrayXXd noise(nn, nn);
      for (std::uint32_t y = 0; y < nn; ++y) {
        for (std::uint32_t x = 0; x < nn; ++x) noise(x, y) = GetF32(in);
      }
      tile.SetNoise(noise, noise_pixel);
    }
    tile.SetStatistics(residual, index);
    return tile;
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(std::string("tile file: ") + e.what());
  }
}

PeriodicTile PeriodicTile::LoadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("tile file: cannot open " + path);
  return Load(in);
}

}  // namespace haptex::tactile
