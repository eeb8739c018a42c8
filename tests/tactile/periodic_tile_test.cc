#include "libs/tactile/periodic_tile.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include <gtest/gtest.h>

#include "libs/tactile/grey_image.h"
#include "libs/tactile/spectrum.h"

namespace haptex::tactile {
namespace {

// Sheared cell with a smooth periodic pattern in cell coordinates.
PeriodicTile ShearedTile() {
  Eigen::Matrix2d basis;
  basis << 0.4e-3, 0.2e-3, 0.0, 0.5e-3;
  Eigen::ArrayXXd h(20, 24);
  for (int i = 0; i < 20; ++i) {
    for (int j = 0; j < 24; ++j) {
      h(i, j) = 5.0 * std::sin(2.0 * std::numbers::pi * i / 20.0) + 3.0 * std::cos(2.0 * std::numbers::pi * j / 24.0);
    }
  }
  return PeriodicTile(basis, Eigen::Vector2d(1e-4, -2e-4), h);
}

TEST(PeriodicTileTest, RepeatsOverItsLattice) {
  const PeriodicTile dut = ShearedTile();
  const Eigen::Matrix2d b = dut.basis_m();
  for (const Eigen::Vector2d& p :
       {Eigen::Vector2d(0.0123, 0.0456), Eigen::Vector2d(-0.003, 0.1), Eigen::Vector2d(0.0, 0.0)}) {
    const double h = dut.HeightUm(p.x(), p.y());
    for (const Eigen::Vector2d& n : {Eigen::Vector2d(1, 0), Eigen::Vector2d(0, 1), Eigen::Vector2d(-7, 13)}) {
      const Eigen::Vector2d q = p + b * n;
      EXPECT_NEAR(dut.HeightUm(q.x(), q.y()), h, 1e-9);
    }
  }
}

TEST(PeriodicTileTest, LookupHitsTheSamples) {
  const PeriodicTile dut = ShearedTile();
  const Eigen::ArrayXXd samples = dut.TileHeightsUm();
  const Eigen::Vector2d p = dut.origin_m() + dut.basis_m() * Eigen::Vector2d(3.0 / 20.0, 5.0 / 24.0);
  EXPECT_NEAR(dut.HeightUm(p.x(), p.y()), samples(3, 5), 1e-9);
}

TEST(PeriodicTileTest, SaveLoadRoundTrip) {
  PeriodicTile dut = ShearedTile();
  Eigen::ArrayXXd noise(8, 8);
  for (Eigen::Index k = 0; k < noise.size(); ++k) noise(k) = 0.1 * static_cast<double>(k % 5);
  dut.SetNoise(noise, 20e-6);
  dut.SetStatistics(0.7, 0.93);
  std::stringstream buffer;
  dut.Save(buffer);
  const PeriodicTile back = PeriodicTile::Load(buffer);
  EXPECT_EQ(back.basis_m(), dut.basis_m());
  EXPECT_EQ(back.origin_m(), dut.origin_m());
  EXPECT_EQ(back.noise_size(), 8);
  EXPECT_DOUBLE_EQ(back.residual_rms_um(), 0.7);
  EXPECT_DOUBLE_EQ(back.periodicity_index(), 0.93);
  for (double u = 0.0; u < 2e-3; u += 0.13e-3) {
    EXPECT_NEAR(back.HeightUm(u, 0.7 * u), dut.HeightUm(u, 0.7 * u), 1e-5);  // heights stored as float32
  }
  // Byte size: 96-byte header, then float32 samples.
  EXPECT_EQ(buffer.str().size(), 96u + 4u * (20u * 24u + 64u));
}

TEST(PeriodicTileTest, CorruptFilesAreRejected) {
  std::stringstream good;
  ShearedTile().Save(good);
  const std::string bytes = good.str();
  std::istringstream truncated(bytes.substr(0, bytes.size() - 3));
  EXPECT_THROW(PeriodicTile::Load(truncated), std::runtime_error);
  std::string bad_magic = bytes;
  bad_magic[0] = 'X';
  std::istringstream magic(bad_magic);
  EXPECT_THROW(PeriodicTile::Load(magic), std::runtime_error);
  std::string degenerate = bytes;
  for (int i = 24; i < 56; ++i) degenerate[static_cast<std::size_t>(i)] = 0;  // basis = 0
  std::istringstream zero(degenerate);
  EXPECT_THROW(PeriodicTile::Load(zero), std::runtime_error);
}

TEST(PeriodicTileTest, SmoothingAttenuatesAGratingAsAGaussian) {
  const double period = 0.5e-3, sigma = 0.1e-3;
  Eigen::Matrix2d basis;
  basis << period, 0.0, 0.0, period;
  Eigen::ArrayXXd h(32, 4);
  for (int i = 0; i < 32; ++i) h.row(i).setConstant(10.0 * std::sin(2.0 * std::numbers::pi * i / 32.0));
  const PeriodicTile smooth = PeriodicTile(basis, Eigen::Vector2d::Zero(), h).Smoothed(sigma);
  const double expected =
      10.0 * std::exp(-2.0 * std::numbers::pi * std::numbers::pi * sigma * sigma / (period * period));
  EXPECT_NEAR(smooth.HeightUm(period / 4.0, 0.0), expected, 1e-6);
}

TEST(PeriodicTileTest, BadConstructionThrows) {
  Eigen::Matrix2d collinear;
  collinear << 1e-3, 2e-3, 1e-3, 2e-3;
  EXPECT_THROW(PeriodicTile(collinear, Eigen::Vector2d::Zero(), Eigen::ArrayXXd::Zero(4, 4)), std::invalid_argument);
  PeriodicTile dut = ShearedTile();
  EXPECT_THROW(dut.SetNoise(Eigen::ArrayXXd::Zero(6, 6), 1e-5), std::invalid_argument);
}

TEST(PeriodicTileTest, WritesTileAndSpectrumImages) {
  const PeriodicTile dut = ShearedTile();
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "haptex_tactile_tile_test";
  std::filesystem::create_directories(dir);
  const HeightMap rendered(dut.Render(128, 128, 10e-6), 10e-6);
  const GreyImage tile_image = GreyImageFromArray(rendered.height_um());
  const GreyImage spectrum_image = GreyImageFromArray(SpectrumImage(ComputePowerSpectrum(rendered)));
  WritePgmFile(tile_image, (dir / "tile.pgm").string());
  WritePngFile(spectrum_image, (dir / "spectrum.png").string());
  const GreyImage back = ReadPgmFile((dir / "tile.pgm").string());
  EXPECT_EQ(back.pixels, tile_image.pixels);
  EXPECT_GT(std::filesystem::file_size(dir / "spectrum.png"), 128u * 128u);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace haptex::tactile
