// The pinch's sample kernels: each against the per-sample law it vectorises, and the AVX2 build
// against the portable one bit for bit.
#include "libs/contact/pinch_sample_lanes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "libs/base/cpu_features.h"

namespace haptex::contact::internal {
namespace {

// A patch of random triangles over random particles, with samples_per_triangle samples each.
struct Fixture {
  int particles = 40, triangles = 30, per = 4, chunks = 1;
  double k_full = 2.0;
  std::vector<double> x_C;  // 4 per particle
  std::vector<std::array<int, 3>> triangle_p;
  std::vector<double> lane_w, lane_k_full, w_sum_full{0.0, 0.0, 0.0}, lane_wk_full;
  std::vector<double> ideal_x, ideal_y, k;
  std::vector<long long> sliding;

  Fixture(int samples_per_triangle, unsigned seed) : per(samples_per_triangle), chunks((per + 3) / 4) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-0.01, 0.01), unit(0.0, 1.0);
    x_C.assign(4 * static_cast<std::size_t>(particles), 0.0);
    for (int p = 0; p < particles; ++p) {
      for (int i = 0; i < 3; ++i) x_C[static_cast<std::size_t>(4 * p + i)] = u(rng);
    }
    for (int t = 0; t < triangles; ++t) triangle_p.push_back({t, t + 1, t + 2 + t % 3});
    lane_w.assign(12 * static_cast<std::size_t>(chunks), 0.0);
    lane_k_full.assign(4 * static_cast<std::size_t>(chunks), 0.0);
    for (int j = 0; j < per; ++j) {
      const double a = 0.1 + 0.8 * unit(rng), b = (1.0 - a) * unit(rng);
      const double w[3] = {a, b, 1.0 - a - b};
      for (int m = 0; m < 3; ++m) {
        lane_w[static_cast<std::size_t>(12 * (j / 4) + 4 * m + j % 4)] = w[m];
        w_sum_full[static_cast<std::size_t>(m)] += w[m];
      }
      lane_k_full[static_cast<std::size_t>(4 * (j / 4) + j % 4)] = k_full;
    }
    for (std::size_t i = 0; i < lane_w.size(); ++i) {
      lane_wk_full.push_back(lane_w[i] * lane_k_full[4 * (i / 12) + i % 4]);
    }
    const std::size_t lanes = static_cast<std::size_t>(triangles * 4 * chunks);
    ideal_x.assign(lanes, 0.0);
    ideal_y.assign(lanes, 0.0);
    k.assign(lanes, 0.0);
    sliding.assign(lanes, 0);
    for (int t = 0; t < triangles; ++t) {
      for (int j = 0; j < per; ++j) {
        const std::size_t l = Lane(t, j);
        ideal_x[l] = u(rng);
        ideal_y[l] = u(rng);
        k[l] = j % 3 == 2 ? 0.0 : k_full * (0.2 + unit(rng));  // some inactive
        sliding[l] = unit(rng) < 0.3 ? -1 : 0;
      }
    }
  }
  std::size_t Lane(int t, int j) const { return static_cast<std::size_t>(t * 4 * chunks + j); }
  double W(int j, int m) const { return lane_w[static_cast<std::size_t>(12 * (j / 4) + 4 * m + j % 4)]; }
  double X(int p, int i) const { return x_C[static_cast<std::size_t>(4 * p + i)]; }
  PinchSampleLayout Layout() const {
    return {chunks, lane_w.data(), lane_k_full.data(), w_sum_full.data(), k_full, lane_wk_full.data()};
  }
  PinchSampleArrays Arrays() { return {ideal_x.data(), ideal_y.data(), k.data(), sliding.data()}; }
};

template <typename T>
bool SameBits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

TEST(PinchSampleLanesTest, FrictionFollowsTheCoulombLawPerSample) {
  // Loaded (every fourth triangle at the full spring) and without grip (no friction).
  for (const bool loaded : {true, false})
    for (int per : {1, 4, 9}) {
      Fixture f(per, 7u + static_cast<unsigned>(per));
      const Fixture before = f;
      std::vector<int> triangles;
      std::vector<std::uint8_t> full;
      for (int t = 0; t < f.triangles; ++t) {
        triangles.push_back(t);
        full.push_back(t % 4 == 0 ? 1 : 0);
      }
      PinchFrictionInput in;
      in.list.x_C_m = f.x_C.data();
      in.list.triangle_p = f.triangle_p.data();
      in.list.triangles = triangles.data();
      in.full = full.data();
      in.list.num_triangles = f.triangles;
      in.normal_per_stiffness_m = loaded ? 0.004 : 0.0;
      in.mu_static = 0.8;
      in.mu_dynamic = 0.4;
      std::vector<PinchParticleSums> sums(static_cast<std::size_t>(f.particles));
      std::vector<double> w_sums(static_cast<std::size_t>(f.particles), 0.0);
      const PinchFrictionTotals totals =
          ApplyPinchFriction(f.Layout(), in, f.Arrays(), sums.data(), w_sums.data(), false);

      // The law sample by sample, and the sums.
      std::vector<PinchParticleSums> ref(static_cast<std::size_t>(f.particles));
      std::vector<double> ref_w(static_cast<std::size_t>(f.particles), 0.0);
      double kix = 0.0, kiy = 0.0;
      int sliding = 0, changed = 0, stuck = 0;
      for (int t = 0; t < f.triangles; ++t) {
        const auto& p = f.triangle_p[static_cast<std::size_t>(t)];
        for (int j = 0; j < per; ++j) {
          const std::size_t l = f.Lane(t, j);
          const double k = full[static_cast<std::size_t>(t)] ? f.k_full : before.k[l];
          if (!(k > 0.0)) {
            EXPECT_EQ(f.ideal_x[l], before.ideal_x[l]);
            EXPECT_EQ(f.sliding[l], before.sliding[l]);
            continue;
          }
          double q[3] = {0.0, 0.0, 0.0};
          for (int i = 0; i < 3; ++i) {
            for (int m = 0; m < 3; ++m) q[i] += f.W(j, m) * f.X(p[static_cast<std::size_t>(m)], i);
          }
          const double normal = in.normal_per_stiffness_m * k;
          const double mu = before.sliding[l] ? in.mu_dynamic : in.mu_static;
          const double sx = q[0] - before.ideal_x[l], sy = q[1] - before.ideal_y[l];
          const double stretch = std::hypot(sx, sy);
          double ix = before.ideal_x[l], iy = before.ideal_y[l];
          if (!loaded) {  // follows q, keeps its flag
            ix = q[0];
            iy = q[1];
            EXPECT_EQ(f.ideal_x[l], ix);
            EXPECT_EQ(f.ideal_y[l], iy);
            EXPECT_EQ(f.sliding[l], before.sliding[l]);
            sliding += before.sliding[l] ? 1 : 0;
            ++changed;
            ++stuck;
          } else if (k * stretch <= mu * normal) {
            EXPECT_EQ(f.sliding[l], 0);
            EXPECT_EQ(f.ideal_x[l], ix);
            EXPECT_EQ(f.ideal_y[l], iy);
            ++stuck;
          } else {
            // Trails q at mu_d of the load, along the stretch.
            ix = q[0] - in.mu_dynamic * normal / k * sx / stretch;
            iy = q[1] - in.mu_dynamic * normal / k * sy / stretch;
            EXPECT_EQ(f.sliding[l], -1);
            EXPECT_NEAR(f.ideal_x[l], ix, 1e-15);
            EXPECT_NEAR(f.ideal_y[l], iy, 1e-15);
            ++sliding;
            ++changed;
          }
          kix += k * ix;
          kiy += k * iy;
          const double d[3] = {ix - q[0], iy - q[1], -q[2]};
          for (int m = 0; m < 3; ++m) {
            PinchParticleSums& r = ref[static_cast<std::size_t>(p[static_cast<std::size_t>(m)])];
            const double wk = f.W(j, m) * k;
            r.kd_x_N += wk * d[0];
            r.kd_y_N += wk * d[1];
            r.kd_z_N += wk * d[2];
            r.k_N_per_m += wk;
            ref_w[static_cast<std::size_t>(p[static_cast<std::size_t>(m)])] += f.W(j, m);
          }
        }
      }
      EXPECT_GT(changed, 0) << per;  // the fixture exercises both branches
      EXPECT_GT(stuck, 0) << per;
      EXPECT_EQ(totals.sliding, sliding);
      EXPECT_NEAR(totals.k_ideal_x_N, kix, 1e-14);
      EXPECT_NEAR(totals.k_ideal_y_N, kiy, 1e-14);
      for (std::size_t p = 0; p < ref.size(); ++p) {
        EXPECT_NEAR(sums[p].kd_x_N, ref[p].kd_x_N, 1e-14);
        EXPECT_NEAR(sums[p].kd_y_N, ref[p].kd_y_N, 1e-14);
        EXPECT_NEAR(sums[p].kd_z_N, ref[p].kd_z_N, 1e-14);
        EXPECT_NEAR(sums[p].k_N_per_m, ref[p].k_N_per_m, 1e-13);
        EXPECT_NEAR(w_sums[p], ref_w[p], 1e-13);
      }
    }
}

PinchAxis Axis(double ax, double ay, double az, double bx, double by, double bz) {
  PinchAxis axis;
  const double a[3] = {ax, ay, az}, ab[3] = {bx - ax, by - ay, bz - az};
  for (int i = 0; i < 3; ++i) {
    axis.a[i] = a[i];
    axis.ab[i] = ab[i];
  }
  const double len2 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
  axis.inv_len2 = len2 > 0.0 ? 1.0 / len2 : 0.0;
  return axis;
}

double DistanceToAxis(const PinchAxis& axis, const double q[3]) {
  double t = 0.0;
  for (int i = 0; i < 3; ++i) t += (q[i] - axis.a[i]) * axis.ab[i];
  t = std::clamp(t * axis.inv_len2, 0.0, 1.0);
  double d2 = 0.0;
  for (int i = 0; i < 3; ++i) d2 += std::pow(q[i] - axis.a[i] - t * axis.ab[i], 2);
  return std::sqrt(d2);
}

PinchClassifyInput ClassifyInput(const Fixture& f, const std::vector<int>& triangles,
                                 const std::vector<std::uint8_t>& deep) {
  PinchClassifyInput in;
  in.list.x_C_m = f.x_C.data();
  in.list.triangle_p = f.triangle_p.data();
  in.list.triangles = triangles.data();
  in.deep = deep.data();
  in.list.num_triangles = static_cast<int>(triangles.size());
  in.thumb = Axis(-0.004, 0.0, 0.008, 0.004, 0.0, 0.008);  // capsules above and below the plane
  in.index = Axis(0.0, -0.004, -0.008, 0.0, 0.004, -0.008);
  in.radius_thumb_m = in.radius_index_m = 0.0125;
  in.edge_ramp_m = 0.002;
  const double full = in.radius_thumb_m - in.edge_ramp_m;
  in.full_thumb2 = in.full_index2 = full * full * (1.0 - 1e-9);
  in.out_thumb2 = in.out_index2 = in.radius_thumb_m * in.radius_thumb_m * (1.0 + 1e-9);
  return in;
}

TEST(PinchSampleLanesTest, ClassificationGivesEachSampleItsRampedSpring) {
  for (int per : {1, 4, 9}) {
    Fixture f(per, 3u + static_cast<unsigned>(per));
    const Fixture before = f;
    std::vector<int> triangles;
    std::vector<std::uint8_t> deep;
    for (int t = 0; t < f.triangles; ++t) {
      triangles.push_back(t);
      deep.push_back(t % 5 == 0 ? 1 : 0);
    }
    const PinchClassifyInput in = ClassifyInput(f, triangles, deep);
    std::vector<PinchTriangleHold> hold(triangles.size());
    const PinchClassifyTotals totals = ClassifyPinchSamples(f.Layout(), in, f.Arrays(), hold.data(), false);
    int active = 0, edge = 0, outside = 0, all_full = 0;
    double k_sum = 0.0;
    for (int t = 0; t < f.triangles; ++t) {
      const auto& p = f.triangle_p[static_cast<std::size_t>(t)];
      bool any = false, every_full = true;
      double k_triangle = 0.0;
      int active_triangle = 0;
      for (int j = 0; j < per; ++j) {
        const std::size_t l = f.Lane(t, j);
        double q[3] = {0.0, 0.0, 0.0};
        for (int i = 0; i < 3; ++i) {
          for (int m = 0; m < 3; ++m) q[i] += f.W(j, m) * f.X(p[static_cast<std::size_t>(m)], i);
        }
        double expected = f.k_full;
        if (!deep[static_cast<std::size_t>(t)]) {
          const double depth = std::min(in.radius_thumb_m - DistanceToAxis(in.thumb, q),
                                        in.radius_index_m - DistanceToAxis(in.index, q));
          expected = depth <= 0.0 ? 0.0 : f.k_full * std::min(1.0, depth / in.edge_ramp_m);
          if (expected == 0.0) ++outside;
          if (expected > 0.0 && expected < f.k_full) ++edge;
        }
        EXPECT_NEAR(f.k[l], expected, 1e-9 * f.k_full) << "triangle " << t << " sample " << j;
        const bool now = f.k[l] > 0.0, was = before.k[l] > 0.0;
        if (now && !was) {  // started: sticks where it is
          EXPECT_NEAR(f.ideal_x[l], q[0], 1e-16);
          EXPECT_NEAR(f.ideal_y[l], q[1], 1e-16);
          EXPECT_EQ(f.sliding[l], 0);
        } else {
          EXPECT_EQ(f.ideal_x[l], before.ideal_x[l]);
          EXPECT_EQ(f.ideal_y[l], before.ideal_y[l]);
          EXPECT_EQ(f.sliding[l], before.sliding[l]);
        }
        any = any || now;
        every_full = every_full && f.k[l] == f.k_full;
        k_triangle += f.k[l];
        active_triangle += now ? 1 : 0;
      }
      const PinchTriangleHold h = hold[static_cast<std::size_t>(t)];
      if (every_full) {
        EXPECT_EQ(h, PinchTriangleHold::kAllFull);
        ++all_full;
      } else if (any) {
        EXPECT_EQ(h, PinchTriangleHold::kSome);
        k_sum += k_triangle;
        active += active_triangle;
      } else {
        EXPECT_EQ(h, PinchTriangleHold::kNone);
      }
    }
    EXPECT_GT(edge, 0) << per;  // the fixture reaches the ramp and the outside
    EXPECT_GT(outside, 0) << per;
    EXPECT_EQ(totals.all_full_triangles, all_full);
    EXPECT_EQ(totals.active_not_full, active);
    EXPECT_NEAR(totals.k_not_full_N_per_m, k_sum, 1e-12);
  }
}

// A deep triangle that the last classification left all at the full spring, marked unchanged, is
// only counted: its samples come out as a full classification leaves them, bit for bit.
TEST(PinchSampleLanesTest, UnchangedDeepTrianglesAreCountedAndLeftAsTheyAre) {
  for (const bool avx2 : {false, true}) {
    if (avx2 && !base::CpuHasAvx2()) continue;
    for (int per : {1, 4, 9}) {
      Fixture f(per, 11u + static_cast<unsigned>(per));
      std::vector<int> triangles;
      std::vector<std::uint8_t> deep;
      for (int t = 0; t < f.triangles; ++t) {
        triangles.push_back(t);
        deep.push_back(t % 3 == 0 ? kPinchDeep : kPinchNotDeep);
      }
      std::vector<PinchTriangleHold> hold(triangles.size());
      ClassifyPinchSamples(f.Layout(), ClassifyInput(f, triangles, deep), f.Arrays(), hold.data(), avx2);
      // The next tick: the same geometry, the deep triangles left all full marked unchanged.
      Fixture full = f, skipped = f;
      std::vector<std::uint8_t> marked = deep;
      int unchanged = 0;
      for (std::size_t e = 0; e < deep.size(); ++e) {
        if (deep[e] == kPinchDeep && hold[e] == PinchTriangleHold::kAllFull) {
          marked[e] = kPinchDeepUnchanged;
          ++unchanged;
        }
      }
      ASSERT_GT(unchanged, 0) << per;
      std::vector<PinchTriangleHold> hold_full(triangles.size()), hold_skipped(triangles.size());
      const PinchClassifyTotals a = ClassifyPinchSamples(full.Layout(), ClassifyInput(full, triangles, deep),
                                                         full.Arrays(), hold_full.data(), avx2);
      const PinchClassifyTotals b = ClassifyPinchSamples(skipped.Layout(), ClassifyInput(skipped, triangles, marked),
                                                         skipped.Arrays(), hold_skipped.data(), avx2);
      EXPECT_TRUE(SameBits(full.k, skipped.k) && SameBits(full.ideal_x, skipped.ideal_x) &&
                  SameBits(full.ideal_y, skipped.ideal_y) && SameBits(full.sliding, skipped.sliding))
          << per;
      EXPECT_TRUE(SameBits(hold_full, hold_skipped)) << per;
      EXPECT_EQ(a.all_full_triangles, b.all_full_triangles);
      EXPECT_EQ(a.active_not_full, b.active_not_full);
      EXPECT_EQ(std::memcmp(&a.k_not_full_N_per_m, &b.k_not_full_N_per_m, sizeof(double)), 0);
    }
  }
}

TEST(PinchSampleLanesTest, Avx2AndPortableKernelsGiveTheSameBits) {
  if (!base::CpuHasAvx2()) GTEST_SKIP() << "no AVX2 on this CPU: nothing to compare";
  for (int per : {1, 4, 9}) {
    Fixture a(per, 11u + static_cast<unsigned>(per)), b = a;
    std::vector<int> triangles;
    std::vector<std::uint8_t> deep, full;
    for (int t = 0; t < a.triangles; ++t) {
      triangles.push_back(t);
      deep.push_back(t % 4 == 0 ? 1 : 0);
      full.push_back(t % 6 == 0 ? 1 : 0);
    }
    // Locate: the particles' x_C as if x_W were x_C rotated and shifted.
    std::vector<double> x_W;
    for (int p = 0; p < a.particles; ++p) {
      for (int i = 0; i < 3; ++i) x_W.push_back(a.X(p, i) + 0.001 * i);
    }
    PinchLocateInput locate;
    locate.x_W_m = x_W.data();
    locate.num_particles = a.particles;
    locate.origin_W_m[0] = 0.001;
    const double c = std::cos(0.3), s = std::sin(0.3);
    const double r[9] = {c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0};
    std::copy(r, r + 9, locate.R_CW);
    const PinchClassifyInput in = ClassifyInput(a, triangles, deep);
    locate.thumb = in.thumb;
    locate.index = in.index;
    locate.reach2_m2 = 1e-4;
    locate.in_thumb2 = locate.in_index2 = 1e-4;
    locate.out_thumb2 = locate.out_index2 = 2e-4;
    locate.full_thumb2 = locate.full_index2 = 2e-4;
    const std::size_t padded = 4 * ((static_cast<std::size_t>(a.particles) + 3) / 4);
    std::vector<double> xc[2], dt[2], di[2];
    std::vector<std::uint8_t> near[2], deep_particle[2], beyond[2];
    std::vector<PinchOwned> owned[2];
    for (int v = 0; v < 2; ++v) {
      xc[v].assign(4 * padded, 0.0);
      dt[v].assign(padded, 0.0);
      di[v].assign(padded, 0.0);
      near[v].assign(padded, 0);
      deep_particle[v].assign(padded, 0);
      owned[v].assign(padded, PinchOwned::kNo);
      beyond[v].assign(padded, 0);
      LocatePinchParticles(locate,
                           {xc[v].data(), dt[v].data(), di[v].data(), near[v].data(), deep_particle[v].data(),
                            owned[v].data(), beyond[v].data()},
                           v == 1);
    }
    EXPECT_TRUE(SameBits(xc[0], xc[1]) && SameBits(dt[0], dt[1]) && SameBits(di[0], di[1]) &&
                SameBits(near[0], near[1]) && SameBits(deep_particle[0], deep_particle[1]) &&
                SameBits(owned[0], owned[1]) && SameBits(beyond[0], beyond[1]))
        << per;
    int deep_count = 0;
    for (int p = 0; p < a.particles; ++p) {
      const std::size_t up = static_cast<std::size_t>(p);
      EXPECT_EQ(deep_particle[0][up] != 0, dt[0][up] < locate.full_thumb2 && di[0][up] < locate.full_index2) << p;
      deep_count += deep_particle[0][up];
      EXPECT_EQ(beyond[0][up], (dt[0][up] > locate.out_thumb2 ? 1 : 0) | (di[0][up] > locate.out_index2 ? 2 : 0));
    }
    EXPECT_GT(deep_count, 0) << per;  // the flag is exercised both ways
    EXPECT_LT(deep_count, a.particles) << per;
    // A count that is not a multiple of 4 (the last group loaded particle by particle): the same.
    for (int v = 0; v < 2; ++v) {
      PinchLocateInput fewer = locate;
      fewer.num_particles = a.particles - 3;
      std::vector<double> xc_f(4 * padded, 0.0), dt_f(padded, 0.0), di_f(padded, 0.0);
      std::vector<std::uint8_t> near_f(padded, 0), deep_f(padded, 0), beyond_f(padded, 0);
      std::vector<PinchOwned> owned_f(padded, PinchOwned::kNo);
      LocatePinchParticles(
          fewer, {xc_f.data(), dt_f.data(), di_f.data(), near_f.data(), deep_f.data(), owned_f.data(), beyond_f.data()},
          v == 1 && base::CpuHasAvx2());
      const std::size_t n = static_cast<std::size_t>(fewer.num_particles);
      EXPECT_EQ(std::memcmp(xc_f.data(), xc[0].data(), 4 * n * sizeof(double)), 0);
      EXPECT_EQ(std::memcmp(dt_f.data(), dt[0].data(), n * sizeof(double)), 0);
      EXPECT_EQ(std::memcmp(di_f.data(), di[0].data(), n * sizeof(double)), 0);
      EXPECT_EQ(std::memcmp(near_f.data(), near[0].data(), n), 0);
      EXPECT_EQ(std::memcmp(deep_f.data(), deep_particle[0].data(), n), 0);
      EXPECT_EQ(std::memcmp(owned_f.data(), owned[0].data(), n), 0);
      EXPECT_EQ(std::memcmp(beyond_f.data(), beyond[0].data(), n), 0);
    }

    std::vector<PinchTriangleHold> hold_a(triangles.size()), hold_b(triangles.size());
    const PinchClassifyTotals ca = ClassifyPinchSamples(a.Layout(), in, a.Arrays(), hold_a.data(), false);
    const PinchClassifyTotals cb = ClassifyPinchSamples(b.Layout(), in, b.Arrays(), hold_b.data(), true);
    EXPECT_EQ(std::memcmp(&ca.k_not_full_N_per_m, &cb.k_not_full_N_per_m, sizeof(double)), 0);
    EXPECT_EQ(ca.active_not_full, cb.active_not_full);
    EXPECT_TRUE(SameBits(hold_a, hold_b));

    PinchFrictionInput fin;
    fin.list.x_C_m = a.x_C.data();
    fin.list.triangle_p = a.triangle_p.data();
    fin.list.triangles = triangles.data();
    fin.full = full.data();
    fin.list.num_triangles = a.triangles;
    fin.normal_per_stiffness_m = 0.003;
    fin.mu_static = 0.6;
    fin.mu_dynamic = 0.3;
    std::vector<PinchParticleSums> sa(static_cast<std::size_t>(a.particles)), sb = sa;
    std::vector<double> wa(static_cast<std::size_t>(a.particles), 0.0), wb = wa;
    const PinchFrictionTotals fa = ApplyPinchFriction(a.Layout(), fin, a.Arrays(), sa.data(), wa.data(), false);
    const PinchFrictionTotals fb = ApplyPinchFriction(b.Layout(), fin, b.Arrays(), sb.data(), wb.data(), true);
    EXPECT_EQ(std::memcmp(&fa.k_ideal_x_N, &fb.k_ideal_x_N, 2 * sizeof(double)), 0) << per;
    EXPECT_EQ(fa.sliding, fb.sliding) << per;
    EXPECT_EQ(std::memcmp(sa.data(), sb.data(), sa.size() * sizeof(PinchParticleSums)), 0) << per;
    EXPECT_TRUE(SameBits(wa, wb) && SameBits(a.ideal_x, b.ideal_x) && SameBits(a.ideal_y, b.ideal_y) &&
                SameBits(a.k, b.k) && SameBits(a.sliding, b.sliding))
        << per;
  }
}

}  // namespace
}  // namespace haptex::contact::internal
