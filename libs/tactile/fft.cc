#include "libs/tactile/fft.h"

#include <cmath>
#include <numbers>
#include <utility>
#include <vector>

namespace haptex::tactile {
namespace {

bool IsPowerOfTwo(std::size_t n) { return n != 0 && (n & (n - 1)) == 0; }

// Iterative Cooley-Tukey on a contiguous buffer.
void Radix2(std::vector<std::complex<double>>& a, bool inverse) {
  const std::size_t n = a.size();
  for (std::size_t i = 1, j = 0; i < n; ++i) {
    std::size_t bit = n >> 1;
    for (; j & bit; bit >>= 1) j ^= bit;
    j ^= bit;
    if (i < j) std::swap(a[i], a[j]);
  }
  const double sign = inverse ? 1.0 : -1.0;
  for (std::size_t len = 2; len <= n; len <<= 1) {
    const double angle = sign * 2.0 * std::numbers::pi / static_cast<double>(len);
    const std::complex<double> w_len(std::cos(angle), std::sin(angle));
    for (std::size_t start = 0; start < n; start += len) {
      std::complex<double> w(1.0, 0.0);
      for (std::size_t k = 0; k < len / 2; ++k) {
        const std::complex<double> u = a[start + k];
        const std::complex<double> v = a[start + k + len / 2] * w;
        a[start + k] = u + v;
        a[start + k + len / 2] = u - v;
        w *= w_len;
      }
    }
  }
}

void Direct(std::vector<std::complex<double>>& a, bool inverse) {
  const std::size_t n = a.size();
  const double sign = inverse ? 1.0 : -1.0;
  std::vector<std::complex<double>> out(n);
  for (std::size_t k = 0; k < n; ++k) {
    std::complex<double> sum(0.0, 0.0);
    for (std::size_t j = 0; j < n; ++j) {
      // Reduce k*j mod n first so the angle stays accurate.
      const double angle = sign * 2.0 * std::numbers::pi * static_cast<double>((k * j) % n) / static_cast<double>(n);
      sum += a[j] * std::complex<double>(std::cos(angle), std::sin(angle));
    }
    out[k] = sum;
  }
  a = std::move(out);
}

}  // namespace

std::size_t NextPowerOfTwo(std::size_t n) {
  std::size_t p = 1;
  while (p < n) p <<= 1;
  return p;
}

void Dft1d(std::complex<double>* data, std::size_t n, std::size_t stride, bool inverse) {
  if (n <= 1) return;
  std::vector<std::complex<double>> buffer(n);
  for (std::size_t i = 0; i < n; ++i) buffer[i] = data[i * stride];
  if (IsPowerOfTwo(n)) {
    Radix2(buffer, inverse);
  } else {
    Direct(buffer, inverse);
  }
  const double scale = inverse ? 1.0 / static_cast<double>(n) : 1.0;
  for (std::size_t i = 0; i < n; ++i) data[i * stride] = buffer[i] * scale;
}

void Dft2d(ComplexGrid* grid, bool inverse) {
  const auto nx = static_cast<std::size_t>(grid->rows());
  const auto ny = static_cast<std::size_t>(grid->cols());
  std::complex<double>* base = grid->data();  // column-major: x is contiguous
  for (std::size_t y = 0; y < ny; ++y) Dft1d(base + y * nx, nx, 1, inverse);
  for (std::size_t x = 0; x < nx; ++x) Dft1d(base + x, ny, nx, inverse);
}

}  // namespace haptex::tactile
