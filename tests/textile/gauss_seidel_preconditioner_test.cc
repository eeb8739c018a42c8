#include "libs/textile/gauss_seidel_preconditioner.h"

#include <bit>
#include <cstdint>
#include <cstring>
#include <random>

#include <gtest/gtest.h>
#include <Eigen/LU>

#include "libs/base/cpu_features.h"
#include "libs/textile/fabric_forces.h"
#include "libs/textile/fabric_stepper.h"
#include "libs/textile/fabric_workspace.h"
#include "libs/textile/implicit_euler.h"
#include "libs/textile/kes_material.h"
#include "tests/support/allocation_counter.h"
#include "tests/textile/fabric_textproto.h"
#include "tests/textile/force_jacobian_check.h"
#include "tests/textile/textile_test_util.h"

namespace haptex::textile {
namespace {

// Bit-for-bit comparisons: EXPECT_EQ on values takes -0 for +0 and never matches a NaN.
std::uint64_t Bits(double x) { return std::bit_cast<std::uint64_t>(x); }
// The rows' 3 entries (pads aside: the kernels need not agree there).
bool SameRowBits(const PaddedVector& a, const PaddedVector& b) {
  if (a.rows() != b.rows()) return false;
  for (int r = 0; r < a.rows(); ++r) {
    if (std::memcmp(a.data() + 4 * r, b.data() + 4 * r, 3 * sizeof(double)) != 0) return false;
  }
  return true;
}

FabricModel DenimModel(int n, double size_m) {
  return BuildFabricModel(MaterialFromKes(testing::LoadDatabaseFabric("wang2011_black_denim_11oz")),
                          {size_m, size_m, n, n});
}

// A 2 x 2 cm patch at 1 mm spacing with its border fixed, as under the fingers.
FabricState BorderFixed(const FabricModel& model) {
  FabricState s = MakeRestState(model);
  for (int p : model.mesh.BorderParticles()) s.Fix(p);
  return s;
}

// The system A = M - h df/dv - h^2 df/dx (h = 1 ms) in a deformed, moving state: its blocks
// and the values of its scalar blocks.
struct System {
  std::vector<Eigen::Matrix3d> blocks;
  std::vector<double> scalars;
};

System Assemble(const FabricModel& model, FabricState* s) {
  for (int p = 0; p < model.num_particles; ++p) {
    s->x(p) = s->x(p).cwiseProduct(Eigen::Vector3d(1.01, 0.995, 1.0));
  }
  testing::Perturb(s, 2e-5, 0.05, 3);
  System a;
  a.blocks.assign(static_cast<std::size_t>(model.pattern.num_blocks()), Eigen::Matrix3d::Zero());
  Eigen::VectorXd f = Eigen::VectorXd::Zero(3 * model.num_particles), fv = f;
  ForceSink sink;
  sink.force_N = &f;
  sink.system = &a.blocks;
  sink.dx_scale = -1e-6;
  sink.dv_scale = -1e-3;
  sink.dfdx_v = &fv;
  sink.v = &s->v_W_m_per_s;
  AccumulateForces(model, *s, &sink);
  for (int p = 0; p < model.num_particles; ++p) {
    a.blocks[static_cast<std::size_t>(model.pattern.diag_slot[static_cast<std::size_t>(p)])] +=
        model.mass_kg[p] * Eigen::Matrix3d::Identity();
  }
  for (int slot : model.product_rows.scalar_slot) {
    a.scalars.push_back(a.blocks[static_cast<std::size_t>(slot)](0, 0));
  }
  return a;
}

// The filtered system as a dense matrix: free rows and columns only (others zero).
Eigen::MatrixXd Dense(const FabricModel& model, const FabricState& s, const System& a) {
  const int n = model.num_particles;
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(3 * n, 3 * n);
  for (int r = 0; r < n; ++r) {
    for (int k = model.pattern.row_start[static_cast<std::size_t>(r)];
         k < model.pattern.row_start[static_cast<std::size_t>(r) + 1]; ++k) {
      const int c = model.pattern.cols[static_cast<std::size_t>(k)];
      if (s.mode[static_cast<std::size_t>(r)] == ParticleMode::kFree &&
          s.mode[static_cast<std::size_t>(c)] == ParticleMode::kFree) {
        m.block<3, 3>(3 * r, 3 * c) = a.blocks[static_cast<std::size_t>(k)];
      }
    }
  }
  return m;
}

Eigen::VectorXd RandomFree(const FabricModel& model, const FabricState& s, std::mt19937* rng) {
  std::normal_distribution<double> normal;
  Eigen::VectorXd x(3 * model.num_particles);
  for (int i = 0; i < x.size(); ++i) x[i] = normal(*rng);
  for (int p = 0; p < model.num_particles; ++p) {
    if (s.mode[static_cast<std::size_t>(p)] != ParticleMode::kFree) x.segment<3>(3 * p).setZero();
  }
  return x;
}

PaddedVector Padded(const Eigen::VectorXd& x) {
  PaddedVector p(static_cast<int>(x.size() / 3));
  p.SetRows(x);
  return p;
}

TEST(GaussSeidelPreconditionerTest, SweepsAndSplitProductMatchTheDenseFactors) {
  const FabricModel model = DenimModel(8, 0.007);
  FabricState s = BorderFixed(model);
  const System a = Assemble(model, &s);
  const Eigen::MatrixXd dense = Dense(model, s, a);
  for (double omega : {1.0, 1.4}) {
    GaussSeidelPreconditioner gs(model.product_rows);
    if (omega == 1.0) gs.UsePortableKernel();  // the other kernel at the other omega
    ASSERT_TRUE(
        gs.Update(a.blocks, omega, [&](int r) { return s.mode[static_cast<std::size_t>(r)] == ParticleMode::kFree; }));
    // D_w + L and D_w + U over the free rows; identity elsewhere keeps them invertible.
    const Eigen::Index n3 = dense.rows();
    Eigen::MatrixXd lower = Eigen::MatrixXd::Zero(n3, n3), upper = lower, diag_w = lower;
    for (int r = 0; r < model.num_particles; ++r) {
      const bool free = s.mode[static_cast<std::size_t>(r)] == ParticleMode::kFree;
      diag_w.block<3, 3>(3 * r, 3 * r) =
          free ? Eigen::Matrix3d(dense.block<3, 3>(3 * r, 3 * r) / omega) : Eigen::Matrix3d::Identity();
      for (int c = 0; c < model.num_particles; ++c) {
        if (c < r) lower.block<3, 3>(3 * r, 3 * c) = dense.block<3, 3>(3 * r, 3 * c);
        if (c > r) upper.block<3, 3>(3 * r, 3 * c) = dense.block<3, 3>(3 * r, 3 * c);
      }
    }
    std::mt19937 rng(5);
    const Eigen::VectorXd x = RandomFree(model, s, &rng);
    const PaddedVector px = Padded(x);
    PaddedVector y(model.num_particles), t(model.num_particles), z(model.num_particles);
    gs.ForwardSolve(a.blocks, a.scalars, px, &y);
    EXPECT_LT(((diag_w + lower) * y.Rows() - x).norm(), 1e-10 * x.norm()) << omega;
    gs.BackwardSolve(a.blocks, a.scalars, px, &y);
    EXPECT_LT(((diag_w + upper) * y.Rows() - x).norm(), 1e-10 * x.norm()) << omega;

    const Eigen::MatrixXd split = (diag_w + lower).lu().solve(dense) * (diag_w + upper).inverse();
    const double xy = gs.MultiplySplit(a.blocks, a.scalars, px, &t, &z, &y);
    EXPECT_LT(((diag_w + upper) * t.Rows() - x).norm(), 1e-10 * x.norm()) << omega;  // t = (D_w + U)^-1 x
    const Eigen::VectorXd expected = split * x;
    EXPECT_LT((y.Rows() - expected).norm(), 1e-9 * expected.norm()) << omega;
    EXPECT_NEAR(xy, x.dot(expected), 1e-9 * std::abs(x.dot(expected)));
    for (int p = 0; p < model.num_particles; ++p) {
      if (s.mode[static_cast<std::size_t>(p)] != ParticleMode::kFree) {
        EXPECT_EQ(y.row(p).norm(), 0.0);
      }
      for (const PaddedVector* v : {&y, &t, &z}) {
        EXPECT_EQ(v->data()[4 * p + 3], 0.0) << "pad of row " << p;  // finite rows: zero pads
      }
    }
  }
}

// The paired forward sweep of x and x2 gives the same bits in both kernels.
void ExpectSamePairSweepBits(const GaussSeidelPreconditioner& fast, const GaussSeidelPreconditioner& portable,
                             const System& a, const PaddedVector& x, const PaddedVector& x2) {
  const int n = x.rows();
  PaddedVector ya1(n), wa1(n), yb1(n), wb1(n), ya2(n), wa2(n), yb2(n), wb2(n);
  double pair1[2], pair2[2];
  fast.ForwardSolveDiagonalPair(a.blocks, a.scalars, x, &ya1, &wa1, x2, &yb1, &wb1, pair1);
  portable.ForwardSolveDiagonalPair(a.blocks, a.scalars, x, &ya2, &wa2, x2, &yb2, &wb2, pair2);
  EXPECT_EQ(Bits(pair1[0]), Bits(pair2[0]));
  EXPECT_EQ(Bits(pair1[1]), Bits(pair2[1]));
  EXPECT_TRUE(SameRowBits(ya1, ya2));
  EXPECT_TRUE(SameRowBits(wa1, wa2));
  EXPECT_TRUE(SameRowBits(yb1, yb2));
  EXPECT_TRUE(SameRowBits(wb1, wb2));
}

// The AVX2 and the portable sweeps give the same bits (where the CPU has AVX2).
TEST(GaussSeidelPreconditionerTest, PortableKernelGivesTheSameBits) {
  const FabricModel model = DenimModel(12, 0.011);
  FabricState s = BorderFixed(model);
  const System a = Assemble(model, &s);
  const auto row_free = [&](int r) { return s.mode[static_cast<std::size_t>(r)] == ParticleMode::kFree; };
  GaussSeidelPreconditioner fast(model.product_rows), portable(model.product_rows);
  portable.UsePortableKernel();
  if (!fast.uses_avx2()) GTEST_SKIP() << "no AVX2 on this CPU: only the portable kernel runs";
  ASSERT_TRUE(fast.Update(a.blocks, 1.3, row_free));
  ASSERT_TRUE(portable.Update(a.blocks, 1.3, row_free));
  std::mt19937 rng(9);
  const PaddedVector x = Padded(RandomFree(model, s, &rng));
  const int n = model.num_particles;
  PaddedVector y1(n), y2(n), t1(n), t2(n), z1(n), z2(n);
  fast.ForwardSolve(a.blocks, a.scalars, x, &y1);
  portable.ForwardSolve(a.blocks, a.scalars, x, &y2);
  EXPECT_TRUE(SameRowBits(y1, y2));
  fast.BackwardSolve(a.blocks, a.scalars, x, &y1);
  portable.BackwardSolve(a.blocks, a.scalars, x, &y2);
  EXPECT_TRUE(SameRowBits(y1, y2));
  const double xy1 = fast.MultiplySplit(a.blocks, a.scalars, x, &t1, &z1, &y1);
  const double xy2 = portable.MultiplySplit(a.blocks, a.scalars, x, &t2, &z2, &y2);
  EXPECT_TRUE(SameRowBits(y1, y2));
  EXPECT_TRUE(SameRowBits(t1, t2));
  EXPECT_EQ(Bits(xy1), Bits(xy2));
  const double d1 = fast.MultiplyDiagonal(y1, &z1), d2 = portable.MultiplyDiagonal(y2, &z2);
  EXPECT_TRUE(SameRowBits(z1, z2));
  EXPECT_EQ(Bits(d1), Bits(d2));
  // The fused passes.
  EXPECT_EQ(Bits(fast.ForwardSolveDiagonal(a.blocks, a.scalars, x, &y1, &z1)),
            Bits(portable.ForwardSolveDiagonal(a.blocks, a.scalars, x, &y2, &z2)));
  EXPECT_TRUE(SameRowBits(y1, y2));
  EXPECT_TRUE(SameRowBits(z1, z2));
  ExpectSamePairSweepBits(fast, portable, a, x, Padded(RandomFree(model, s, &rng)));
  PaddedVector c1 = x, c2 = x, u1 = y1, u2 = y2;
  EXPECT_EQ(Bits(fast.UpdateMultiplySplit(a.blocks, a.scalars, u1, 0.7, &c1, &t1, &z1, &y1)),
            Bits(portable.UpdateMultiplySplit(a.blocks, a.scalars, u2, 0.7, &c2, &t2, &z2, &y2)));
  EXPECT_TRUE(SameRowBits(c1, c2));
  EXPECT_TRUE(SameRowBits(y1, y2));
  PaddedVector s1(n), s2(n);
  for (bool y_zero : {false, true}) {
    EXPECT_EQ(Bits(fast.StepResidual(0.3, t1, y1, y_zero, &z1, &c1, &s1)),
              Bits(portable.StepResidual(0.3, t2, y2, y_zero, &z2, &c2, &s2)));
    EXPECT_TRUE(SameRowBits(z1, z2));
    EXPECT_TRUE(SameRowBits(c1, c2));
    EXPECT_TRUE(SameRowBits(s1, s2));
  }
}

// Likewise with every row free: the grid's first and last rows have the shapes the AVX2 kernel
// takes out of its common-row path (fewer blocks, no adjacent one, the last block in memory).
TEST(GaussSeidelPreconditionerTest, PortableKernelGivesTheSameBitsWithEveryRowFree) {
  const FabricModel model = DenimModel(9, 0.008);
  FabricState s = MakeRestState(model);
  const System a = Assemble(model, &s);
  const auto row_free = [](int) { return true; };
  GaussSeidelPreconditioner fast(model.product_rows), portable(model.product_rows);
  portable.UsePortableKernel();
  if (!fast.uses_avx2()) GTEST_SKIP() << "no AVX2 on this CPU: only the portable kernel runs";
  ASSERT_TRUE(fast.Update(a.blocks, 1.3, row_free));
  ASSERT_TRUE(portable.Update(a.blocks, 1.3, row_free));
  std::mt19937 rng(4);
  const PaddedVector x = Padded(RandomFree(model, s, &rng)), x2 = Padded(RandomFree(model, s, &rng));
  const int n = model.num_particles;
  PaddedVector y1(n), y2(n), t1(n), t2(n), z1(n), z2(n), w1(n), w2(n), u1(n), u2(n);
  fast.BackwardSolve(a.blocks, a.scalars, x, &y1);
  portable.BackwardSolve(a.blocks, a.scalars, x, &y2);
  EXPECT_TRUE(SameRowBits(y1, y2));
  ExpectSamePairSweepBits(fast, portable, a, x, x2);
  EXPECT_EQ(Bits(fast.MultiplySplit(a.blocks, a.scalars, x, &t1, &z1, &y1)),
            Bits(portable.MultiplySplit(a.blocks, a.scalars, x, &t2, &z2, &y2)));
  EXPECT_TRUE(SameRowBits(y1, y2));
  EXPECT_TRUE(SameRowBits(t1, t2));
  PaddedVector c1 = x, c2 = x;
  EXPECT_EQ(Bits(fast.UpdateMultiplySplit(a.blocks, a.scalars, x2, 0.7, &c1, &t1, &z1, &y1)),
            Bits(portable.UpdateMultiplySplit(a.blocks, a.scalars, x2, 0.7, &c2, &t2, &z2, &y2)));
  EXPECT_TRUE(SameRowBits(c1, c2));
  EXPECT_TRUE(SameRowBits(t1, t2));
  EXPECT_TRUE(SameRowBits(y1, y2));
  EXPECT_EQ(Bits(fast.StepResidual(0.3, t1, y1, false, &u1, &c1, &w1)),
            Bits(portable.StepResidual(0.3, t2, y2, false, &u2, &c2, &w2)));
  EXPECT_TRUE(SameRowBits(c1, c2));
  EXPECT_TRUE(SameRowBits(w1, w2));
}

// The fused passes CG runs give the bits of the passes they fuse, with either kernel.
TEST(GaussSeidelPreconditionerTest, FusedPassesGiveTheUnfusedBits) {
  const FabricModel model = DenimModel(10, 0.009);
  FabricState s = BorderFixed(model);
  const System a = Assemble(model, &s);
  const auto row_free = [&](int r) { return s.mode[static_cast<std::size_t>(r)] == ParticleMode::kFree; };
  const int n = model.num_particles;
  for (bool portable : {false, true}) {
    GaussSeidelPreconditioner gs(model.product_rows);
    if (portable) gs.UsePortableKernel();
    ASSERT_TRUE(gs.Update(a.blocks, 1.2, row_free));
    std::mt19937 rng(13);
    const PaddedVector x = Padded(RandomFree(model, s, &rng)), u = Padded(RandomFree(model, s, &rng));

    PaddedVector y1(n), w1(n), y2(n), w2(n);
    const double d1 = gs.ForwardSolveDiagonal(a.blocks, a.scalars, x, &y1, &w1);
    gs.ForwardSolve(a.blocks, a.scalars, x, &y2);
    const double d2 = gs.MultiplyDiagonal(y2, &w2);
    EXPECT_EQ(Bits(d1), Bits(d2)) << portable;
    EXPECT_TRUE(SameRowBits(y1, y2)) << portable;
    EXPECT_TRUE(SameRowBits(w1, w2)) << portable;

    // Two forward-diagonal sweeps in one pass.
    PaddedVector yx(n), wx(n), yp(n), wp(n), yu(n), wu(n);
    double pair[2];
    gs.ForwardSolveDiagonalPair(a.blocks, a.scalars, x, &yx, &wx, u, &yp, &wp, pair);
    const double du = gs.ForwardSolveDiagonal(a.blocks, a.scalars, u, &yu, &wu);
    EXPECT_EQ(Bits(pair[0]), Bits(d1)) << portable;
    EXPECT_EQ(Bits(pair[1]), Bits(du)) << portable;
    EXPECT_TRUE(SameRowBits(yx, y1)) << portable;
    EXPECT_TRUE(SameRowBits(wx, w1)) << portable;
    EXPECT_TRUE(SameRowBits(yp, yu)) << portable;
    EXPECT_TRUE(SameRowBits(wp, wu)) << portable;

    // c = u + beta c, then the split product.
    PaddedVector c1 = x, c2 = x, t1(n), t2(n), z1(n), z2(n), q1(n), q2(n);
    const double cq1 = gs.UpdateMultiplySplit(a.blocks, a.scalars, u, 0.4, &c1, &t1, &z1, &q1);
    c2.vec() = u.vec() + 0.4 * c2.vec();
    const double cq2 = gs.MultiplySplit(a.blocks, a.scalars, c2, &t2, &z2, &q2);
    EXPECT_EQ(Bits(cq1), Bits(cq2)) << portable;
    EXPECT_TRUE(SameRowBits(c1, c2)) << portable;
    EXPECT_TRUE(SameRowBits(t1, t2)) << portable;
    EXPECT_TRUE(SameRowBits(q1, q2)) << portable;

    // y += alpha t, r -= alpha q, s = D_w r; and from y = 0.
    for (bool y_zero : {false, true}) {
      PaddedVector ya = u, yb = u, ra = x, rb = x, sa(n), sb(n);
      if (y_zero) yb.SetZero();
      const double da = gs.StepResidual(0.6, t1, q1, y_zero, &ya, &ra, &sa);
      yb.vec() += 0.6 * t1.vec();
      rb.vec() -= 0.6 * q1.vec();
      const double db = gs.MultiplyDiagonal(rb, &sb);
      EXPECT_EQ(Bits(da), Bits(db)) << portable << y_zero;
      EXPECT_TRUE(SameRowBits(ya, yb)) << portable << y_zero;
      EXPECT_TRUE(SameRowBits(ra, rb)) << portable << y_zero;
      EXPECT_TRUE(SameRowBits(sa, sb)) << portable << y_zero;
    }
  }
}

TEST(GaussSeidelPreconditionerTest, SingularDiagonalBlockIsReported) {
  const FabricModel model = DenimModel(5, 0.004);
  FabricState s = BorderFixed(model);
  System a = Assemble(model, &s);
  const int centre = 12;
  a.blocks[static_cast<std::size_t>(model.pattern.diag_slot[centre])].setZero();
  GaussSeidelPreconditioner gs(model.product_rows);
  EXPECT_FALSE(gs.Update(a.blocks, 1.0, [](int) { return true; }));
}

// The implicit step with Gauss-Seidel gives block Jacobi's answer when both solve tightly,
// with far fewer iterations on the stiff 1 mm patch (the haptic patch's case).
TEST(GaussSeidelPreconditionerTest, StepMatchesBlockJacobiWithFewerIterations) {
  const FabricModel model = DenimModel(20, 0.019);
  FabricState a = BorderFixed(model);
  Assemble(model, &a);  // deformed and moving
  FabricState b = a;
  StepOptions gs;
  gs.dt_s = 1e-3;
  gs.cg_tolerance = 1e-9;
  gs.cg_max_iterations = 5000;
  gs.cg_warm_start = false;
  gs.preconditioner = Preconditioner::kGaussSeidel;
  gs.ssor_omega = 1.4;
  StepOptions jacobi = gs;
  jacobi.preconditioner = Preconditioner::kBlockJacobi;
  FabricStepper sa(model, gs), sb(model, jacobi);
  int ia = 0, ib = 0;
  for (int i = 0; i < 10; ++i) {
    const StepResult ra = sa.Step(&a);
    ia += ra.cg.iterations;
    ib += sb.Step(&b).cg.iterations;
    EXPECT_FALSE(ra.cg.preconditioner_fallback);
  }
  EXPECT_LT(ia * 2, ib) << ia << " vs " << ib;
  // Both solve to the same relative residual, not to the same bits: positions move by dt times
  // the velocities, so the velocity bound allows 10 steps x 1 ms x 1e-8 m/s = 1e-10 m (measured
  // 4.5e-11 m since compression follows the tensile slope: a stiffer, worse-conditioned system).
  EXPECT_LT((a.x_W_m - b.x_W_m).cwiseAbs().maxCoeff(), 1e-10);
  EXPECT_LT((a.v_W_m_per_s - b.v_W_m_per_s).cwiseAbs().maxCoeff(), 1e-8);
  EXPECT_EQ(a.diagnostics.cg_not_converged, 0);
  for (int p : model.mesh.BorderParticles()) EXPECT_EQ(a.v(p), Eigen::Vector3d::Zero());
}

// A row's blocks against Eigen, for a block that is not symmetric (a transposed inverse would
// pass on the fabric's near-symmetric blocks), in both builds; singular and non-finite blocks
// are refused.
TEST(GaussSeidelPreconditionerTest, RowBlocksInvertAndPremultiplyExactly) {
  Eigen::Matrix3d a;
  a << 4.0, 1.0, -0.5, 0.3, 3.0, 0.7, -1.2, 0.4, 5.0;
  Eigen::Matrix3d lower_block, upper_block;
  lower_block << 1.0, 2.0, 3.0, -4.0, 5.0, -6.0, 7.0, 8.0, -9.0;
  upper_block = 0.5 * lower_block.transpose();
  const double omega = 1.6;
  const Eigen::Matrix3d d_w = a / omega, d_w_inv = d_w.inverse();
  auto read = [](const internal::PaddedBlock& b) {
    Eigen::Matrix3d m;
    for (int j = 0; j < 3; ++j) {
      for (int i = 0; i < 3; ++i) m(i, j) = b.col[j][i];
      EXPECT_EQ(b.col[j][3], 0.0) << "pad of column " << j;
    }
    return m;
  };
  for (bool avx2 : {false, base::CpuHasAvx2()}) {
    internal::PaddedBlock d, d_inv, lower, upper;
    ASSERT_TRUE(internal::SetRowBlocks(a, omega, &lower_block, &upper_block, avx2, &d, &d_inv, &lower, &upper));
    EXPECT_LT((read(d) - d_w).cwiseAbs().maxCoeff(), 1e-15) << avx2;
    EXPECT_LT((read(d_inv) - d_w_inv).cwiseAbs().maxCoeff(), 1e-14) << avx2;
    EXPECT_LT((read(d_inv) * d_w - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-14) << avx2;
    EXPECT_LT((read(lower) - d_w_inv * lower_block).cwiseAbs().maxCoeff(), 1e-13) << avx2;
    EXPECT_LT((read(upper) - d_w_inv * upper_block).cwiseAbs().maxCoeff(), 1e-13) << avx2;

    Eigen::Matrix3d singular;
    singular << 2.0, 1.0, 0.0, 1.0, 3.0, 1.0, 3.0, 4.0, 1.0;  // row 2 = row 0 + row 1: det exactly 0
    EXPECT_FALSE(internal::SetRowBlocks(singular, omega, nullptr, nullptr, avx2, &d, &d_inv, &lower, &upper));
    EXPECT_FALSE(
        internal::SetRowBlocks(Eigen::Matrix3d::Zero(), omega, nullptr, nullptr, avx2, &d, &d_inv, &lower, &upper));
    Eigen::Matrix3d nan = a;
    nan(1, 2) = std::numeric_limits<double>::quiet_NaN();
    EXPECT_FALSE(internal::SetRowBlocks(nan, omega, nullptr, nullptr, avx2, &d, &d_inv, &lower, &upper));
    Eigen::Matrix3d huge = a;
    huge(0, 0) = std::numeric_limits<double>::infinity();
    EXPECT_FALSE(internal::SetRowBlocks(huge, omega, nullptr, nullptr, avx2, &d, &d_inv, &lower, &upper));
  }
  // Both builds give the same bits.
  internal::PaddedBlock d1, i1, l1, u1, d2, i2, l2, u2;
  internal::SetRowBlocks(a, omega, &lower_block, &upper_block, false, &d1, &i1, &l1, &u1);
  internal::SetRowBlocks(a, omega, &lower_block, &upper_block, base::CpuHasAvx2(), &d2, &i2, &l2, &u2);
  EXPECT_EQ(read(i1), read(i2));
  EXPECT_EQ(read(l1), read(l2));
  // The bits of the textbook order: adj(a)'s columns are cross products of a's rows, and
  // D_w^-1 = adj(a) (omega / det) with det = a's row 0 . adj's column 0.
  const auto cross = [](const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
    return Eigen::Vector3d(u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]);
  };
  Eigen::Matrix3d adj;
  adj.col(0) = cross(a.row(1), a.row(2));
  adj.col(1) = cross(a.row(2), a.row(0));
  adj.col(2) = cross(a.row(0), a.row(1));
  const double det = (a(0, 0) * adj(0, 0) + a(0, 1) * adj(1, 0)) + a(0, 2) * adj(2, 0);
  EXPECT_EQ(read(i1), Eigen::Matrix3d(adj * (omega / det)));
}

// A non-finite state makes a non-finite solve (the stepper rolls it back); the next steps must
// solve normally again, without the block-Jacobi fallback.
TEST(GaussSeidelPreconditionerTest, StepAfterANonFiniteStepSolvesNormally) {
  const FabricModel model = DenimModel(12, 0.011);
  FabricState s = BorderFixed(model);
  StepOptions o;
  o.dt_s = 1e-3;
  o.preconditioner = Preconditioner::kGaussSeidel;
  o.ssor_omega = 1.6;
  FabricStepper stepper(model, o);
  s.v_W_m_per_s.setConstant(0.01);
  ASSERT_EQ(stepper.Step(&s).status, StepStatus::kOk);
  const int interior = 5 * 12 + 5;
  ASSERT_EQ(s.mode[interior], ParticleMode::kFree);
  s.v_W_m_per_s[3 * interior + 2] = std::numeric_limits<double>::infinity();
  EXPECT_EQ(stepper.Step(&s).status, StepStatus::kNanRecovered);
  for (int i = 0; i < 3; ++i) {
    const StepResult r = stepper.Step(&s);
    EXPECT_TRUE(r.cg.finite) << i;
    EXPECT_TRUE(r.cg.converged) << i;
    EXPECT_FALSE(r.cg.preconditioner_fallback) << i;
    EXPECT_EQ(r.status, StepStatus::kOk) << i;
  }
  EXPECT_TRUE(s.x_W_m.allFinite());
}

// A step reads nothing stale from the split system's vectors: with every entry of them (pads
// included) poisoned beforehand it gives the same bits as with fresh ones.
TEST(GaussSeidelPreconditionerTest, StepDoesNotReadStaleSplitVectors) {
  const FabricModel model = DenimModel(12, 0.011);
  FabricState a = BorderFixed(model);
  Assemble(model, &a);  // deformed and moving
  FabricState b = a;
  StepOptions o;
  o.dt_s = 1e-3;
  o.preconditioner = Preconditioner::kGaussSeidel;
  o.cg_max_iterations = 6;
  FabricWorkspace fresh(model, o.preconditioner), poisoned(model, o.preconditioner);
  FabricWorkspace::SplitVectors& v = poisoned.split;
  for (PaddedVector* p : {&v.r, &v.c, &v.q, &v.s, &v.t, &v.z, &v.y}) {
    p->vec().setConstant(std::numeric_limits<double>::quiet_NaN());
  }
  const CgReport ra = ImplicitEulerStep(model, o, &a, &fresh).cg;
  const CgReport rb = ImplicitEulerStep(model, o, &b, &poisoned).cg;
  EXPECT_TRUE(rb.finite);
  EXPECT_FALSE(rb.preconditioner_fallback);
  EXPECT_EQ(ra.iterations, rb.iterations);
  EXPECT_EQ(a.x_W_m, b.x_W_m);
  EXPECT_EQ(a.v_W_m_per_s, b.v_W_m_per_s);
}

// The sweeps skip the rows that are not free: with free runs of every length, at both ends of
// the rows, each pass solves its triangular system, writes zeros (not left garbage) in those
// rows of its outputs, and gives the same bits into poisoned outputs as into fresh ones.
TEST(GaussSeidelPreconditionerTest, SkippedRowsAreZeroedAndRunsSolveExactly) {
  const FabricModel model = DenimModel(7, 0.006);
  FabricState s = MakeRestState(model);
  for (int p : {1, 4, 5, 9, 10, 11, 20, 30, 31, 47}) s.Fix(p);  // row 0 and row 48 free
  const System a = Assemble(model, &s);
  const Eigen::MatrixXd dense = Dense(model, s, a);
  const int n = model.num_particles;
  const auto free = [&](int r) { return s.mode[static_cast<std::size_t>(r)] == ParticleMode::kFree; };
  const auto poisoned = [n] {
    PaddedVector v(n);
    v.vec().setConstant(std::numeric_limits<double>::quiet_NaN());
    return v;
  };
  const auto zero_where_fixed = [&](const PaddedVector& v) {
    for (int r = 0; r < n; ++r) {
      if (free(r)) continue;
      for (int i = 0; i < 4; ++i) {
        if (Bits(v.data()[4 * r + i]) != 0) return false;
      }
    }
    return true;
  };
  for (bool portable : {false, true}) {
    GaussSeidelPreconditioner gs(model.product_rows);
    if (portable) gs.UsePortableKernel();
    ASSERT_TRUE(gs.Update(a.blocks, 1.3, free));
    Eigen::MatrixXd lower = Eigen::MatrixXd::Zero(3 * n, 3 * n), upper = lower;
    for (int r = 0; r < n; ++r) {
      for (int c = 0; c < n; ++c) {
        const Eigen::Matrix3d b = dense.block<3, 3>(3 * r, 3 * c);
        if (c == r) {
          lower.block<3, 3>(3 * r, 3 * r) = free(r) ? Eigen::Matrix3d(b / 1.3) : Eigen::Matrix3d::Identity();
          upper.block<3, 3>(3 * r, 3 * r) = lower.block<3, 3>(3 * r, 3 * r);
        }
        if (c < r) lower.block<3, 3>(3 * r, 3 * c) = b;
        if (c > r) upper.block<3, 3>(3 * r, 3 * c) = b;
      }
    }
    std::mt19937 rng(17);
    const Eigen::VectorXd xv = RandomFree(model, s, &rng);
    const PaddedVector x = Padded(xv), u = Padded(RandomFree(model, s, &rng));

    PaddedVector y = poisoned();
    gs.ForwardSolve(a.blocks, a.scalars, x, &y);
    EXPECT_LT((lower * y.Rows() - xv).norm(), 1e-10 * xv.norm()) << portable;
    EXPECT_TRUE(zero_where_fixed(y)) << portable;
    gs.BackwardSolve(a.blocks, a.scalars, x, &y);
    EXPECT_LT((upper * y.Rows() - xv).norm(), 1e-10 * xv.norm()) << portable;
    EXPECT_TRUE(zero_where_fixed(y)) << portable;

    PaddedVector y1(n), w1(n), y2(n), w2(n), y3 = poisoned(), w3 = poisoned(), y4 = poisoned(), w4 = poisoned();
    double fresh[2], dirty[2];
    gs.ForwardSolveDiagonalPair(a.blocks, a.scalars, x, &y1, &w1, u, &y2, &w2, fresh);
    gs.ForwardSolveDiagonalPair(a.blocks, a.scalars, x, &y3, &w3, u, &y4, &w4, dirty);
    EXPECT_EQ(Bits(fresh[0]), Bits(dirty[0])) << portable;
    EXPECT_EQ(Bits(fresh[1]), Bits(dirty[1])) << portable;
    for (const auto& [f, d] : {std::pair{&y1, &y3}, {&w1, &w3}, {&y2, &y4}, {&w2, &w4}}) {
      EXPECT_TRUE(SameRowBits(*f, *d)) << portable;
      EXPECT_TRUE(zero_where_fixed(*d)) << portable;
    }

    PaddedVector c1 = x, t1(n), z1(n), q1(n), c2 = x, t2 = poisoned(), z2 = poisoned(), q2 = poisoned();
    EXPECT_EQ(Bits(gs.UpdateMultiplySplit(a.blocks, a.scalars, u, 0.6, &c1, &t1, &z1, &q1)),
              Bits(gs.UpdateMultiplySplit(a.blocks, a.scalars, u, 0.6, &c2, &t2, &z2, &q2)))
        << portable;
    for (const auto& [f, d] : {std::pair{&c1, &c2}, {&t1, &t2}, {&z1, &z2}, {&q1, &q2}}) {
      EXPECT_TRUE(SameRowBits(*f, *d)) << portable;
      EXPECT_TRUE(zero_where_fixed(*d)) << portable;
    }
  }
}

// StepResidual updates only the free rows: with the zeros CG keeps in the others (t, q, r, s,
// and y after its first step) that gives the bits of updating all rows, and with y_zero it
// writes y's zeros there over stale values; a non-finite alpha updates all rows.
TEST(GaussSeidelPreconditionerTest, StepResidualSkipsRowsThatAreNotFree) {
  const FabricModel model = DenimModel(7, 0.006);
  FabricState s = MakeRestState(model);
  for (int p : {1, 4, 5, 9, 10, 11, 20, 30, 31, 47}) s.Fix(p);
  const System a = Assemble(model, &s);
  const int n = model.num_particles;
  const auto free = [&](int r) { return s.mode[static_cast<std::size_t>(r)] == ParticleMode::kFree; };
  for (bool portable : {false, true}) {
    GaussSeidelPreconditioner gs(model.product_rows);
    if (portable) gs.UsePortableKernel();
    ASSERT_TRUE(gs.Update(a.blocks, 1.3, free));
    std::mt19937 rng(19);
    const PaddedVector t = Padded(RandomFree(model, s, &rng)), q = Padded(RandomFree(model, s, &rng));
    const PaddedVector r0 = Padded(RandomFree(model, s, &rng)), y0 = Padded(RandomFree(model, s, &rng));
    for (double alpha : {0.7, std::numeric_limits<double>::infinity()}) {
      for (bool y_zero : {false, true}) {
        PaddedVector y = y0, r = r0, sv(n), y_ref = y0, r_ref = r0, s_ref(n);
        if (y_zero) {
          y.vec().setConstant(std::numeric_limits<double>::quiet_NaN());  // stale: not read
          y_ref.SetZero();
        }
        const double xy = gs.StepResidual(alpha, t, q, y_zero, &y, &r, &sv);
        y_ref.vec() += alpha * t.vec();
        r_ref.vec() -= alpha * q.vec();
        const double xy_ref = gs.MultiplyDiagonal(r_ref, &s_ref);
        EXPECT_EQ(Bits(xy), Bits(xy_ref)) << portable << y_zero << alpha;
        EXPECT_TRUE(SameRowBits(y, y_ref)) << portable << y_zero << alpha;
        EXPECT_TRUE(SameRowBits(r, r_ref)) << portable << y_zero << alpha;
        EXPECT_TRUE(SameRowBits(sv, s_ref)) << portable << y_zero << alpha;
      }
    }
  }
}

// Update after an Update with other free rows gives a fresh preconditioner's bits (rows no
// longer free are zeroed, rows still not free are left zero).
TEST(GaussSeidelPreconditionerTest, UpdateWithOtherFreeRowsMatchesAFreshOne) {
  const FabricModel model = DenimModel(7, 0.006);
  FabricState s = MakeRestState(model);
  for (int p : {1, 4, 5, 9, 10}) s.Fix(p);
  const System first = Assemble(model, &s);
  for (int p : {11, 20, 30, 31, 47}) s.Fix(p);
  const System a = Assemble(model, &s);
  const int n = model.num_particles;
  const auto free = [&](int r) { return s.mode[static_cast<std::size_t>(r)] == ParticleMode::kFree; };
  const auto all_but_4 = [](int r) { return r != 4; };
  for (bool portable : {false, true}) {
    GaussSeidelPreconditioner reused(model.product_rows), fresh(model.product_rows);
    if (portable) {
      reused.UsePortableKernel();
      fresh.UsePortableKernel();
    }
    ASSERT_TRUE(reused.Update(first.blocks, 1.3, all_but_4));
    ASSERT_TRUE(reused.Update(first.blocks, 1.3, [&](int r) { return r > 2 && r != 9 && r != 10; }));
    ASSERT_TRUE(reused.Update(a.blocks, 1.3, free));
    ASSERT_TRUE(fresh.Update(a.blocks, 1.3, free));
    std::mt19937 rng(23);
    const PaddedVector x = Padded(RandomFree(model, s, &rng));
    PaddedVector t1(n), z1(n), y1(n), t2(n), z2(n), y2(n);
    EXPECT_EQ(Bits(reused.MultiplySplit(a.blocks, a.scalars, x, &t1, &z1, &y1)),
              Bits(fresh.MultiplySplit(a.blocks, a.scalars, x, &t2, &z2, &y2)))
        << portable;
    EXPECT_TRUE(SameRowBits(y1, y2)) << portable;
    EXPECT_TRUE(SameRowBits(t1, t2)) << portable;
    // D_w times a vector with no zero rows: D_w must be 0 in the rows that are not free.
    PaddedVector full(n);
    for (int i = 0; i < 4 * n; ++i) full.data()[i] = i % 4 == 3 ? 0.0 : 1.0 + i;
    EXPECT_EQ(Bits(reused.MultiplyDiagonal(full, &z1)), Bits(fresh.MultiplyDiagonal(full, &z2))) << portable;
    EXPECT_TRUE(SameRowBits(z1, z2)) << portable;
  }
}

TEST(GaussSeidelPreconditionerTest, OmegaOutsideZeroTwoIsRefused) {
  StepOptions o;
  o.preconditioner = Preconditioner::kGaussSeidel;
  for (double omega : {0.0, 2.0, -1.0, std::numeric_limits<double>::quiet_NaN()}) {
    o.ssor_omega = omega;
    EXPECT_THROW(ValidateStepOptions(o), std::invalid_argument) << omega;
  }
}

TEST(GaussSeidelPreconditionerTest, WarmedUpStepDoesNotAllocate) {
  if (!haptex::testing::AllocationCountingSupported()) GTEST_SKIP() << "allocation counting off (ASan)";
  const FabricModel model = DenimModel(12, 0.011);
  FabricState s = BorderFixed(model);
  StepOptions o;
  o.dt_s = 1e-3;
  o.preconditioner = Preconditioner::kGaussSeidel;
  FabricStepper stepper(model, o);
  s.v_W_m_per_s.setConstant(0.01);
  stepper.Step(&s);
  haptex::testing::AllocationCounter counter;
  for (int i = 0; i < 10; ++i) stepper.Step(&s);
  EXPECT_EQ(counter.count(), 0);
}

}  // namespace
}  // namespace haptex::textile
