#include "libs/textile/fabric_forces.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include <Eigen/Geometry>

#include "libs/base/cpu_features.h"
#include "libs/base/demand.h"
#include "libs/base/lanes.h"

#ifdef HAPTEX_X86_KERNELS
#include <immintrin.h>
#endif

namespace haptex::textile {
namespace {

// The per-force functions (tensile_force.cc, shear_force.cc, bending_force.cc, drag_force.cc)
// are the reference; this file evaluates the same forces and Jacobians in one pass per element,
// writing each system block once (dx and dv terms combined) and computing (df/dx) v per element
// instead of per block. tests/textile/fabric_forces_test.cc checks the two agree.
//
// Triangles go four at a time: lane j of a V4 is triangle t + j (structure of arrays), so every
// element operation is one 4-wide operation. A GCC/Clang vector extension: pairs of SSE2
// operations in the generic build, one AVX operation in the avx2 build. Both builds do the same
// IEEE operations in the same order (no FMA), so the results do not depend on the CPU. Forces
// and (df/dx) v are the one-triangle formulas, added per lane in triangle order (triangles of a
// group share particles). Blocks (l, k) are blocks (k, l) transposed, and a group's terms reach
// a shared block in block order: the system differs from a triangle-by-triangle sum by rounding.
// The lane helpers (V4, Splat, Sqrt, Any, Transpose, ...) are libs/base/lanes.h's.
using base::lanes::Abs;
using base::lanes::Any;
using base::lanes::Dot3;
using base::lanes::kLanes;
using base::lanes::M4;
using base::lanes::Splat;
using base::lanes::Sqrt;
using base::lanes::Transpose;
using base::lanes::V2;
using base::lanes::V4;

// base[index[j]] in lane j.
HAPTEX_LANES_INLINE V4 Gather(const double* base, const int index[kLanes]) {
  return V4{base[index[0]], base[index[1]], base[index[2]], base[index[3]]};
}
// base[index[j]] and base[index[j] + 1] in lane j of *first and *second: four 2-wide loads and
// one transpose instead of two gathers.
HAPTEX_LANES_INLINE void GatherPairs(const double* base, const int index[kLanes], V4* first, V4* second) {
  V2 pair[kLanes];
  HAPTEX_UNROLL
  for (int j = 0; j < kLanes; ++j) std::memcpy(&pair[j], base + index[j], sizeof pair[j]);
  const V4 lanes02 = __builtin_shufflevector(pair[0], pair[2], 0, 1, 2, 3);  // f0 s0 f2 s2
  const V4 lanes13 = __builtin_shufflevector(pair[1], pair[3], 0, 1, 2, 3);  // f1 s1 f3 s3
  *first = __builtin_shufflevector(lanes02, lanes13, 0, 4, 2, 6);
  *second = __builtin_shufflevector(lanes02, lanes13, 1, 5, 3, 7);
}
// Coordinates (x, y, z) of four particles, base + offset[j] in lane j.
HAPTEX_LANES_INLINE void GatherXyz(const double* base, const int offset[kLanes], V4 out[3]) {
  GatherPairs(base, offset, &out[0], &out[1]);
  out[2] = Gather(base + 2, offset);
}
static_assert(offsetof(TriangleElement, b) == offsetof(TriangleElement, a) + 3 * sizeof(double),
              "the triangle kernel loads a and b as one run of 6 doubles");
// *p = *from + a for 4 doubles (a Matrix3d's data: 8-byte aligned only).
HAPTEX_LANES_INLINE void AddTo(V4 a, const double* from, double* p) {
  V4 b;
  std::memcpy(&b, from, sizeof b);
  b += a;
  std::memcpy(p, &b, sizeof b);
}

// out[corner k of lane j's triangle] += v[k][.][j], lane by lane in triangle order (the
// triangles of a group share particles). corner[k][j] is the offset of that particle's
// coordinates. Each corner is one 2-wide (x, y) and one scalar (z) add; the (x, y) pairs of
// lanes 0, 2 and 1, 3 are the halves of two unpacks (fewer shuffles than a full transpose).
HAPTEX_LANES_INLINE void ScatterToCorners(const V4 v[3][3], const int corner[3][kLanes], int lanes, double* out) {
  V2 xy[3][kLanes];
  HAPTEX_UNROLL
  for (int k = 0; k < 3; ++k) {
    const V4 xy02 = __builtin_shufflevector(v[k][0], v[k][1], 0, 4, 2, 6);  // x0 y0 x2 y2
    const V4 xy13 = __builtin_shufflevector(v[k][0], v[k][1], 1, 5, 3, 7);  // x1 y1 x3 y3
    xy[k][0] = __builtin_shufflevector(xy02, xy02, 0, 1);
    xy[k][1] = __builtin_shufflevector(xy13, xy13, 0, 1);
    xy[k][2] = __builtin_shufflevector(xy02, xy02, 2, 3);
    xy[k][3] = __builtin_shufflevector(xy13, xy13, 2, 3);
  }
  // Unrolled over all four lanes (constant lane indices keep the vectors in registers); the
  // tail group stops early (for full groups lanes is the constant kLanes: no test remains).
  HAPTEX_UNROLL
  for (int j = 0; j < kLanes; ++j) {
    if (j == lanes) break;
    HAPTEX_UNROLL
    for (int k = 0; k < 3; ++k) {
      double* o = out + corner[k][j];
      V2 sum;
      std::memcpy(&sum, o, sizeof sum);
      sum += xy[k][j];
      std::memcpy(o, &sum, sizeof sum);
      o[2] += v[k][2][j];
    }
  }
}

// Where a group's triangles add their blocks: system blocks at byte offsets offsets[j] for lane
// j, read from sources[first[j][kl]]: the system itself, or for first additions the base (the
// system when the sink has no base). A table lookup: no per-block bit test or select.
struct BlockTarget {
  const std::array<std::int32_t, 9>* offsets;  // FabricModel::triangle_block_offsets
  const std::array<std::uint8_t, 9>* first;    // FabricModel::triangle_first_blocks
  Eigen::Matrix3d* system;
  const Eigen::Matrix3d* const* sources;  // {system, base}
};

// Block = from + m, m the block entries of lane j, at slot index kl: two 4-wide and one scalar
// add. `from` is the block itself or, for its first addition, its base.
HAPTEX_LANES_INLINE void AddBlock(const BlockTarget& t, int j, int kl, V4 lo, V4 hi, double m8) {
  const auto e = static_cast<std::size_t>(kl);
  const std::ptrdiff_t offset = t.offsets[j][e];
  auto* block = reinterpret_cast<double*>(reinterpret_cast<char*>(t.system) + offset);
  const auto* from_blocks = reinterpret_cast<const char*>(t.sources[t.first[j][e]]);
  const auto* from = reinterpret_cast<const double*>(from_blocks + offset);
  AddTo(lo, from, block);
  AddTo(hi, from + 4, block + 4);
  block[8] = from[8] + m8;
}

// Adds block entries m (entry e of lanes 0..3) to the block at slot index kl of each lane's
// triangle.
HAPTEX_LANES_INLINE void AddBlocks(const V4 m[9], const BlockTarget& t, int lanes, int kl) {
  V4 lo[kLanes], hi[kLanes];
  Transpose(m, lo);
  Transpose(m + 4, hi);
  HAPTEX_UNROLL
  for (int j = 0; j < kLanes; ++j) {  // unrolled as in ScatterToCorners
    if (j == lanes) break;
    AddBlock(t, j, kl, lo[j], hi[j], m[8][j]);
  }
}

// AddBlocks of m at slot index kl, then of its transpose at lk. The transposed lanes come from
// the untransposed ones: (m0 m3 m6 m1) and (m4 m7 m2 m5) are (m0..m3) and (m4..m7) permuted
// (0 3 2 1) with entries 2 swapped: four shuffles a lane instead of two more transposes.
HAPTEX_LANES_INLINE void AddBlockPair(const V4 m[9], const BlockTarget& t, int lanes, int kl, int lk) {
  V4 lo[kLanes], hi[kLanes];
  Transpose(m, lo);
  Transpose(m + 4, hi);
  const auto add = [&](int j, int slot_index, V4 first, V4 second)
                       HAPTEX_LANES_LAMBDA { AddBlock(t, j, slot_index, first, second, m[8][j]); };
  HAPTEX_UNROLL
  for (int j = 0; j < kLanes; ++j) {  // unrolled as in ScatterToCorners
    if (j == lanes) break;
    add(j, kl, lo[j], hi[j]);
  }
  HAPTEX_UNROLL
  for (int j = 0; j < kLanes; ++j) {
    if (j == lanes) break;
    const V4 plo = __builtin_shufflevector(lo[j], lo[j], 0, 3, 2, 1);
    const V4 phi = __builtin_shufflevector(hi[j], hi[j], 0, 3, 2, 1);
    add(j, lk, __builtin_shufflevector(plo, phi, 0, 1, 6, 3), __builtin_shufflevector(phi, plo, 0, 1, 6, 3));
  }
}

// A strain curve read through its public interface (StrainCurve, MonotoneSpline), evaluated for
// four strains with the arithmetic of StrainCurve::Evaluate, so to the same values.
struct CurveLanes {
  const double* x;
  const double* y;
  const double* m;
  int last;  // index of the last knot
  double compression_N_per_m;
  bool odd;
  int top_step;  // first step of the segment search (0 for a single segment)
};

CurveLanes LanesOf(const StrainCurve& curve) {
  const MonotoneSpline& s = curve.loading();
  HAPTEX_DEMAND(s.knots_x().size() >= 2);
  const int last = static_cast<int>(s.knots_x().size()) - 1;
  // Steps top_step, top_step / 2, ..., 1 reach segment 2 top_step - 1 from segment 0.
  int top_step = 0, reach = 0;
  while (reach < last - 1) {
    top_step = top_step == 0 ? 1 : 2 * top_step;
    reach = 2 * top_step - 1;
  }
  return {s.knots_x().data(),
          s.knots_y().data(),
          s.tangents().data(),
          last,
          curve.compression_N_per_m(),
          curve.odd(),
          top_step};
}

HAPTEX_LANES_INLINE void Evaluate(const CurveLanes* c, V4 strain, V4* f, V4* df) {
  const M4 negative = ~(strain >= 0.0);
  const V4 arg = c->odd ? (negative ? -strain : strain) : strain;
  const double x0 = c->x[0], x_last = c->x[c->last];
  // Per lane: the last segment k with x_k <= arg (the one holding an interior strain; outside
  // the knots the linear ends below replace the lane). Binary lifting with conditional moves:
  // strains of neighbouring triangles scatter over a few segments, so a walk from the previous
  // lane's segment mispredicted its branches.
  V4 xk, xk1, yk, yk1, mk, mk1;
  if (c->top_step == 0) {  // one segment (as the shear curve): no search, no gathers
    xk = Splat(c->x[0]), xk1 = Splat(c->x[1]);
    yk = Splat(c->y[0]), yk1 = Splat(c->y[1]);
    mk = Splat(c->m[0]), mk1 = Splat(c->m[1]);
  } else {
    int seg[kLanes];
    for (int j = 0; j < kLanes; ++j) {
      const double a = arg[j];
      int k = 0;
      for (int step = c->top_step; step > 0; step >>= 1) {
        const int probe = std::min(k + step, c->last - 1);
        k = c->x[probe] <= a ? probe : k;
      }
      seg[j] = k;
    }
    GatherPairs(c->x, seg, &xk, &xk1);
    GatherPairs(c->y, seg, &yk, &yk1);
    GatherPairs(c->m, seg, &mk, &mk1);
  }
  const V4 h = xk1 - xk;
  const V4 t = (arg - xk) / h;
  const V4 t2 = t * t;
  const V4 t3 = t2 * t;
  const V4 h00 = 2.0 * t3 - 3.0 * t2 + 1.0, h10 = t3 - 2.0 * t2 + t, h01 = -2.0 * t3 + 3.0 * t2, h11 = t3 - t2;
  V4 y = h00 * yk + h10 * h * mk + h01 * yk1 + h11 * h * mk1;
  const V4 d00 = 6.0 * t2 - 6.0 * t, d10 = 3.0 * t2 - 4.0 * t + 1.0, d01 = -6.0 * t2 + 6.0 * t,
           d11 = 3.0 * t2 - 2.0 * t;
  V4 dy = (d00 * yk + d01 * yk1) / h + d10 * mk + d11 * mk1;
  // Linear beyond the end knots, with the end tangents.
  const M4 above = arg >= x_last;
  y = above ? c->y[c->last] + c->m[c->last] * (arg - x_last) : y;
  dy = above ? Splat(c->m[c->last]) : dy;
  const M4 below = arg <= x0;
  y = below ? c->y[0] + c->m[0] * (arg - x0) : y;
  dy = below ? Splat(c->m[0]) : dy;
  if (c->odd) {
    *f = negative ? -y : y;
    *df = dy;
  } else {
    *f = negative ? c->compression_N_per_m * strain : y;
    *df = negative ? Splat(c->compression_N_per_m) : dy;
  }
}

// One tensile direction of four triangles: d = sum w_k x_k. Its force on corner k is
// -A (sigma + c dir.d_dot) w_k dir = -area_total w_k dir (the caller forms it). Its Jacobian
// blocks are A_kl = w_k w_l (beta dir dir^T + alpha I) (dx and dv combined, scaled by the sink),
// and -A kx d_dot (times w_k) is its (df/dx) v. Everything is zero in a
// collapsed element's lane (no defined direction), so the caller adds the terms unconditionally.
struct DirectionLanes {
  V4 dir[3];
  V4 area_total;  // A (sigma + c dir.d_dot)
  V4 beta, alpha;
  V4 kx_ddot[3];
};

HAPTEX_LANES_INLINE void TensileDirection(V4 area, const CurveLanes* curve, double damping_s, const V4 d[3],
                                          const V4 d_dot[3], bool jacobians, double dx_scale, double dv_scale,
                                          DirectionLanes* out) {
  const V4 len = Sqrt(Dot3(d, d));
  const M4 live = len > 1e-12;  // else collapsed: no defined direction
  const V4 inv_len = 1.0 / len;
  V4* dir = out->dir;
  HAPTEX_UNROLL
  for (int i = 0; i < 3; ++i) dir[i] = live ? d[i] * inv_len : Splat(0.0);
  V4 sigma, slope;
  Evaluate(curve, len - 1.0, &sigma, &slope);
  const V4 c = damping_s * slope;
  const V4 dir_ddot = Dot3(dir, d_dot);
  const V4 total = live ? sigma + c * dir_ddot : Splat(0.0);
  out->area_total = area * total;
  if (!jacobians) return;
  // kx = slope ddT + t (I - ddT), t = max(sigma, 0) / len; kv = c ddT.
  const V4 t = (sigma < 0.0 ? Splat(0.0) : sigma) * inv_len;
  out->beta = live ? -area * (dx_scale * (slope - t) + dv_scale * c) : Splat(0.0);
  out->alpha = live ? -area * dx_scale * t : Splat(0.0);
  const V4 along = (slope - t) * dir_ddot;
  HAPTEX_UNROLL
  for (int i = 0; i < 3; ++i) {
    out->kx_ddot[i] = live ? -area * (along * dir[i] + t * d_dot[i]) : Splat(0.0);
  }
}

// Entry (i, j) of beta dir dir^T + alpha I.
HAPTEX_LANES_INLINE V4 StiffnessEntry(const DirectionLanes& d, int i, int j) {
  const V4 e = d.beta * d.dir[i] * d.dir[j];
  return i == j ? e + d.alpha : e;
}

// The order TriangleKernel adds a group's blocks k*3+l in (its add_pair and add_negated_pair
// calls), each to all lanes before the next: TriangleFirstBlocks follows it.
constexpr std::array<int, 9> kTriangleBlockOrder = {0, 1, 3, 4, 2, 6, 5, 7, 8};

// Tensile (warp, weft), shear and quadratic drag of every triangle; each of its 9 system blocks
// is one sum of rank-one terms, written once.
HAPTEX_LANES_INLINE void TriangleKernel(const FabricModel& model, const double* xp, const double* vp, ForceSink* sink) {
  const bool jac = sink->wants_jacobians();
  const double dxs = sink->dx_scale, dvs = sink->dv_scale;
  const double stretch_s = model.options.damping.stretch_s;
  const double shear_s = model.options.damping.shear_s;
  const DragOptions& drag = model.options.drag;
  const double q = 0.5 * drag.air_density_kg_per_m3 * drag.quadratic_coefficient;
  const CurveLanes warp_curve = LanesOf(model.material.tensile_warp);
  const CurveLanes weft_curve = LanesOf(model.material.tensile_weft);
  const CurveLanes shear_curve = LanesOf(model.material.shear);
  double* fp = sink->force_N->data();
  double* dfv = jac ? sink->dfdx_v->data() : nullptr;
  Eigen::Matrix3d* system = jac ? sink->system->data() : nullptr;
  const Eigen::Matrix3d* base = jac && sink->system_base != nullptr ? sink->system_base : system;
  // Model data in locals: the force stores could alias it, so it would be reloaded.
  const TriangleElement* triangles = model.triangles.data();
  const std::size_t num_triangles = model.triangles.size();
  HAPTEX_DEMAND(model.triangle_block_offsets.size() == num_triangles);
  const std::array<std::int32_t, 9>* offsets_all = model.triangle_block_offsets.data();
  HAPTEX_DEMAND(model.triangle_first_blocks.size() == num_triangles);
  const std::array<std::uint8_t, 9>* first_blocks = model.triangle_first_blocks.data();
  const Eigen::Matrix3d* const sources[2] = {system, base};
  // One group of four triangles from t0; `lanes` of them real. The tail group repeats its last
  // triangle in the unused lanes (computed, never scattered).
  const auto group = [&](std::size_t t0, int lanes) HAPTEX_LANES_LAMBDA {
    const TriangleElement* el[kLanes];
    HAPTEX_UNROLL
    for (int j = 0; j < kLanes; ++j) el[j] = triangles + t0 + std::min(j, lanes - 1);
    // Lanes gathered into registers (GatherXyz, GatherPairs): lane-by-lane stores to a vector
    // in memory would stall its next load.
    int corner[3][kLanes];  // 3 x particle index: offset of corner k's coordinates
    HAPTEX_UNROLL
    for (int k = 0; k < 3; ++k) {
      HAPTEX_UNROLL
      for (int j = 0; j < kLanes; ++j) corner[k][j] = 3 * el[j]->p[static_cast<std::size_t>(k)];
    }
    const V4 area = V4{el[0]->area_m2, el[1]->area_m2, el[2]->area_m2, el[3]->area_m2};
    // The weights a_0 a_1 a_2 b_0 b_1 b_2 are contiguous in a TriangleElement: two 4-wide loads a
    // lane (from a_0 and from a_2) and transposes instead of 24 scalar loads and inserts.
    V4 weights_lo[kLanes], weights_hi[kLanes];
    HAPTEX_UNROLL
    for (int j = 0; j < kLanes; ++j) {
      const char* weights = reinterpret_cast<const char*>(el[j]) + offsetof(TriangleElement, a);
      std::memcpy(&weights_lo[j], weights, sizeof weights_lo[j]);
      std::memcpy(&weights_hi[j], weights + 2 * sizeof(double), sizeof weights_hi[j]);
    }
    V4 lo_rows[4], hi_rows[4];  // a_0 a_1 a_2 b_0 and a_2 b_0 b_1 b_2 of lanes 0..3
    Transpose(weights_lo, lo_rows);
    Transpose(weights_hi, hi_rows);
    const V4 a[3] = {lo_rows[0], lo_rows[1], lo_rows[2]};
    const V4 b[3] = {lo_rows[3], hi_rows[2], hi_rows[3]};
    V4 xk[3][3], vk[3][3];  // [corner][axis]
    HAPTEX_UNROLL
    for (int k = 0; k < 3; ++k) {
      GatherXyz(xp, corner[k], xk[k]);
      GatherXyz(vp, corner[k], vk[k]);
    }
    V4 u[3], w[3], u_dot[3], w_dot[3];
    HAPTEX_UNROLL
    for (int i = 0; i < 3; ++i) {
      u[i] = a[0] * xk[0][i] + a[1] * xk[1][i] + a[2] * xk[2][i];
      w[i] = b[0] * xk[0][i] + b[1] * xk[1][i] + b[2] * xk[2][i];
      u_dot[i] = a[0] * vk[0][i] + a[1] * vk[1][i] + a[2] * vk[2][i];
      w_dot[i] = b[0] * vk[0][i] + b[1] * vk[1][i] + b[2] * vk[2][i];
    }
    // Tensile, warp and weft.
    DirectionLanes warp{}, weft{};
    TensileDirection(area, &warp_curve, stretch_s, u, u_dot, jac, dxs, dvs, &warp);
    TensileDirection(area, &weft_curve, stretch_s, w, w_dot, jac, dxs, dvs, &weft);

    // Shear: gamma = U.V, d gamma / d x_k = g_k = a_k V + b_k U.
    V4 g[3][3];
    V4 gamma_dot = Splat(0.0);
    HAPTEX_UNROLL
    for (int k = 0; k < 3; ++k) {
      HAPTEX_UNROLL
      for (int i = 0; i < 3; ++i) g[k][i] = a[k] * w[i] + b[k] * u[i];
      gamma_dot += Dot3(g[k], vk[k]);
    }
    V4 tau, shear_slope;
    Evaluate(&shear_curve, Dot3(u, w), &tau, &shear_slope);
    const V4 shear_c = shear_s * shear_slope;
    const V4 shear_total = tau + shear_c * gamma_dot;
    const V4 shear_f = area * shear_total;

    // Quadratic drag on the normal velocity (Jacobian in v only): dq n n^T per block; zero in a
    // lane whose triangle has (numerically) no area.
    V4 n[3] = {};
    V4 dq = Splat(0.0), fc = Splat(0.0);
    bool drag_force = false;
    if (q > 0.0) {
      V4 e1[3], e2[3], vm[3];
      HAPTEX_UNROLL
      for (int i = 0; i < 3; ++i) {
        e1[i] = xk[1][i] - xk[0][i];
        e2[i] = xk[2][i] - xk[0][i];
      }
      const V4 cross[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
      const V4 twice_area = Sqrt(Dot3(cross, cross));
      const M4 live = twice_area > 1e-14;
      if (Any(live)) {
        const V4 inv_twice_area = 1.0 / twice_area;
        HAPTEX_UNROLL
        for (int i = 0; i < 3; ++i) {
          n[i] = live ? cross[i] * inv_twice_area : Splat(0.0);
          vm[i] = (vk[0][i] + vk[1][i] + vk[2][i]) / 3.0;
        }
        const V4 vn = Dot3(n, vm);
        const V4 drag_area = 0.5 * twice_area;
        fc = live ? -q * drag_area * vn * Abs(vn) / 3.0 : Splat(0.0);
        drag_force = true;
        dq = live ? dvs * (-q * drag_area * 2.0 * Abs(vn) / 9.0) : Splat(0.0);
      }
    }

    // Forces, each entry summed in the order warp, weft, shear, drag. Formed here, not term by
    // term above: fewer vectors live through the curve evaluations (register spills).
    // The membrane forces of a triangle sum to zero (linear shape functions, as the blocks
    // below): corner 2's is minus the sum of the others'.
    V4 f[3][3];
    HAPTEX_UNROLL
    for (int k = 0; k < 2; ++k) {
      const V4 s_warp = warp.area_total * a[k], s_weft = weft.area_total * b[k];
      HAPTEX_UNROLL
      for (int i = 0; i < 3; ++i) {
        f[k][i] = Splat(0.0) - s_warp * warp.dir[i] - s_weft * weft.dir[i] - shear_f * g[k][i];
      }
    }
    HAPTEX_UNROLL
    for (int i = 0; i < 3; ++i) {
      const V4 drag_i = drag_force ? fc * n[i] : Splat(0.0);
      f[2][i] = drag_i - (f[0][i] + f[1][i]);
      if (drag_force) {
        f[0][i] += drag_i;
        f[1][i] += drag_i;
      }
    }
    ScatterToCorners(f, corner, lanes, fp);
    if (!jac) return;

    // (df/dx) v per particle.
    const V4 shear_kx = -area * shear_slope * gamma_dot;
    const V4 shear_sys = -area * (dxs * shear_slope + dvs * shear_c);
    V4 dk[3][3];  // summing to zero over the corners, as the membrane forces
    HAPTEX_UNROLL
    for (int k = 0; k < 2; ++k) {
      HAPTEX_UNROLL
      for (int i = 0; i < 3; ++i) {
        dk[k][i] = shear_kx * g[k][i] + a[k] * warp.kx_ddot[i] + b[k] * weft.kx_ddot[i];
      }
    }
    HAPTEX_UNROLL
    for (int i = 0; i < 3; ++i) dk[2][i] = Splat(0.0) - (dk[0][i] + dk[1][i]);
    ScatterToCorners(dk, corner, lanes, dfv);

    // Blocks (k, l) = M_kl + dq n n^T, the membrane part M_kl = shear_sys g_k g_l^T +
    // a_k a_l K_warp + b_k b_l K_weft with K = beta dir dir^T + alpha I, entry (i, j) at i + 3 j
    // (column-major). Linear shape functions: a_0 + a_1 + a_2 = b_0 + b_1 + b_2 = 0, so
    // g_0 + g_1 + g_2 = 0 and each row of membrane blocks sums to zero. M_00, M_01 and M_11 are
    // formed (M_10 = M_01^T); with S_0 = M_00 + M_01 and S_1 = M_01^T + M_11, M_02 = -S_0,
    // M_12 = -S_1 and M_22 = S_0^T + S_1^T.
    // Symmetric matrices (the K, the drag term, the diagonal blocks) are formed on and above
    // the diagonal and mirrored: exactly symmetric, in fewer operations.
    const auto mirror = [](V4 m[9]) HAPTEX_LANES_LAMBDA { m[1] = m[3], m[2] = m[6], m[5] = m[7]; };
    constexpr bool kUpper[9] = {true, false, false, true, true, false, true, true, true};
    V4 k_warp[9], k_weft[9], k_drag[9], shear_p[2][3];
    HAPTEX_UNROLL
    for (int e = 0; e < 9; ++e) {
      if (!kUpper[e]) continue;
      k_warp[e] = StiffnessEntry(warp, e % 3, e / 3);
      k_weft[e] = StiffnessEntry(weft, e % 3, e / 3);
      k_drag[e] = dq * n[e % 3] * n[e / 3];
    }
    mirror(k_warp), mirror(k_weft), mirror(k_drag);
    HAPTEX_UNROLL
    for (int k = 0; k < 2; ++k) {
      HAPTEX_UNROLL
      for (int i = 0; i < 3; ++i) shear_p[k][i] = shear_sys * g[k][i];
    }
    const bool drag_active = Any(dq != 0.0);
    const BlockTarget target{&offsets_all[t0], &first_blocks[t0], system, sources};
    const auto membrane = [&](int k, int l, V4 m[9]) HAPTEX_LANES_LAMBDA {
      const V4 aa = a[k] * a[l], bb = b[k] * b[l];
      HAPTEX_UNROLL
      for (int e = 0; e < 9; ++e) {
        if (k == l && !kUpper[e]) continue;
        m[e] = shear_p[k][e % 3] * g[l][e / 3] + aa * k_warp[e] + bb * k_weft[e];
      }
      if (k == l) mirror(m);
    };
    // Adds block (k, l) = m (plus drag) and block (l, k) = its transpose.
    const auto add_pair = [&](int k, int l, V4 m[9]) HAPTEX_LANES_LAMBDA {
      if (drag_active) {
        HAPTEX_UNROLL
        for (int e = 0; e < 9; ++e) {
          if (k != l || kUpper[e]) m[e] += k_drag[e];
        }
        if (k == l) mirror(m);
      }
      if (l == k) {
        AddBlocks(m, target, lanes, k * 3 + l);
      } else {
        AddBlockPair(m, target, lanes, k * 3 + l, l * 3 + k);
      }
    };
    // -s (plus drag) as drag - s: one operation per entry either way.
    const auto add_negated_pair = [&](int k, int l, const V4 s[9]) HAPTEX_LANES_LAMBDA {
      V4 m[9];
      HAPTEX_UNROLL
      for (int e = 0; e < 9; ++e) m[e] = (drag_active ? k_drag[e] : Splat(0.0)) - s[e];
      AddBlockPair(m, target, lanes, k * 3 + l, l * 3 + k);
    };
    V4 s0[9], s1[9];
    {
      V4 m00[9], m01[9], m11[9];
      membrane(0, 0, m00);
      membrane(0, 1, m01);
      membrane(1, 1, m11);
      HAPTEX_UNROLL
      for (int e = 0; e < 9; ++e) {
        s0[e] = m00[e] + m01[e];
        s1[e] = m01[3 * (e % 3) + e / 3] + m11[e];
      }
      add_pair(0, 0, m00);
      add_pair(0, 1, m01);
      add_pair(1, 1, m11);
    }
    add_negated_pair(0, 2, s0);
    add_negated_pair(1, 2, s1);
    V4 m22[9];
    HAPTEX_UNROLL
    for (int e = 0; e < 9; ++e) {
      const int t = 3 * (e % 3) + e / 3;  // entry e of the transpose
      if (kUpper[e]) m22[e] = s0[t] + s1[t];
    }
    mirror(m22);
    add_pair(2, 2, m22);
  };
  // Full groups with the lane count a constant: no per-lane tail tests in the scatters.
  std::size_t t0 = 0;
  for (; t0 + kLanes <= num_triangles; t0 += kLanes) group(t0, kLanes);
  if (t0 < num_triangles) group(t0, static_cast<int>(num_triangles - t0));
}

void AddTriangleForcesGeneric(const FabricModel& model, const double* x, const double* v, ForceSink* sink) {
  TriangleKernel(model, x, v, sink);
}

#ifdef HAPTEX_X86_KERNELS
// The same kernel on 256-bit registers. No FMA: the products round as in the generic build.
__attribute__((target("avx2"))) void AddTriangleForcesAvx2(const FabricModel& model, const double* x, const double* v,
                                                           ForceSink* sink) {
  TriangleKernel(model, x, v, sink);
}
// The same 256-bit kernel on AVX-512VL's 32 vector registers: the ~40 vectors the Jacobian
// blocks need spill far less (this kernel is instruction-bound). Same width and operations, no
// FMA: the same bits.
__attribute__((target("avx2,avx512f,avx512vl"))) void AddTriangleForcesAvx2On32Registers(const FabricModel& model,
                                                                                         const double* x,
                                                                                         const double* v,
                                                                                         ForceSink* sink) {
  TriangleKernel(model, x, v, sink);
}

#endif

void AddTriangleForces(const FabricModel& model, const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                       internal::ForceKernels kernels, ForceSink* sink) {
  using internal::ForceKernels;
#ifdef HAPTEX_X86_KERNELS
  // Else SIGILL.
  HAPTEX_DEMAND(kernels == ForceKernels::kPortable || base::CpuHasAvx2());
  HAPTEX_DEMAND(kernels != ForceKernels::kAvx2On32Registers || base::CpuHasAvx512Vl());
  if (kernels == ForceKernels::kAvx2On32Registers) {
    return AddTriangleForcesAvx2On32Registers(model, x.data(), v.data(), sink);
  }
  if (kernels == ForceKernels::kAvx2) return AddTriangleForcesAvx2(model, x.data(), v.data(), sink);
#else
  HAPTEX_DEMAND(kernels == ForceKernels::kPortable);
#endif
  AddTriangleForcesGeneric(model, x.data(), v.data(), sink);
}

// (x, y) as one 2-wide vector and z alone: the IEEE operations of the scalar formulas, per
// component, in fewer instructions (AddLinearDragAndLoads runs in the base build: SSE2 on
// x86-64).
struct Xyz {
  V2 xy;
  double z;
};
inline Xyz LoadXyz(const double* p) {
  Xyz r;
  std::memcpy(&r.xy, p, sizeof r.xy);
  r.z = p[2];
  return r;
}

// The constant Jacobian blocks of bending with its damping: lambda alpha_k alpha_l I, scaled.
void AddBendingBlocks(const FabricModel& model, ForceSink* sink) {
  const double damping_s = model.options.damping.bend_s;
  std::vector<Eigen::Matrix3d>& system = *sink->system;
  for (std::size_t b = 0; b < model.bends.size(); ++b) {
    const BendElement& e = model.bends[b];
    const double scale = -e.lambda_N_per_m * (sink->dx_scale + sink->dv_scale * damping_s);
    for (std::size_t k = 0; k < 3; ++k) {
      for (std::size_t l = 0; l < 3; ++l) {
        system[static_cast<std::size_t>(model.bend_slots[b][k * 3 + l])].diagonal().array() +=
            scale * e.alpha[k] * e.alpha[l];
      }
    }
  }
}

// Bending on (x, y, z, -) in one V4 per particle: the IEEE operations of the scalar formulas,
// per component (lane 3 is never stored). A particle is one masked load in the avx2 build (it
// never reads past the particle), an (x, y) pair and z in the portable one.
#ifdef HAPTEX_X86_KERNELS
// Not always_inline: its avx2 target would not match the template's; flatten on the avx2
// kernel inlines it there.
__attribute__((target("avx2"))) inline V4 Load3Avx2(const double* p) {
  return _mm256_maskload_pd(p, _mm256_set_epi64x(0, -1, -1, -1));
}
#endif
template <bool kAvx2>
HAPTEX_LANES_INLINE V4 Load3(const double* p) {
#ifdef HAPTEX_X86_KERNELS
  if constexpr (kAvx2) return Load3Avx2(p);
#endif
  V2 xy;
  std::memcpy(&xy, p, sizeof xy);
  return __builtin_shufflevector(xy, V2{p[2], p[2]}, 0, 1, 2, 3);  // z twice: one load
}
HAPTEX_LANES_INLINE void Store3(V4 a, double* p) {
  const V2 xy = __builtin_shufflevector(a, a, 0, 1);
  std::memcpy(p, &xy, sizeof xy);
  p[2] = a[2];
}

// Volino's linear bending with damping: forces, and (df/dx) v into dfv unless null (kDfv).
// Bends along a grid line come in chains, each starting at the previous one's corners 1 and 2:
// those two particles' sums stay in registers, so each bend loads and stores one particle's
// instead of three. Every particle's sum is still added to in bend order: the bits of one bend
// at a time.
template <bool kAvx2, bool kDfv>
HAPTEX_LANES_INLINE void BendingKernel(const FabricModel& model, const double* xp, const double* vp, double* fp,
                                       double* dfv) {
  const double damping_s = model.options.damping.bend_s;
  // Model data in locals: the force stores could alias it, so it would be reloaded.
  const BendElement* bends = model.bends.data();
  const std::size_t num_bends = model.bends.size();
  std::size_t b = 0;
  while (b < num_bends) {
    int o0 = 3 * bends[b].p[0], o1 = 3 * bends[b].p[1], o2 = 3 * bends[b].p[2];
    // Sums of corners 0 and 1 (a triplet with a repeated particle is a chain of one).
    const bool distinct = o0 != o1 && o0 != o2 && o1 != o2;
    V4 f0 = Load3<kAvx2>(fp + o0), f1 = Load3<kAvx2>(fp + o1), d0{}, d1{};
    if constexpr (kDfv) d0 = Load3<kAvx2>(dfv + o0), d1 = Load3<kAvx2>(dfv + o1);
    // Positions and velocities of corners 0 and 1, also carried along the chain.
    V4 x0 = Load3<kAvx2>(xp + o0), x1 = Load3<kAvx2>(xp + o1);
    V4 v0 = Load3<kAvx2>(vp + o0), v1 = Load3<kAvx2>(vp + o1);
    for (;;) {
      const BendElement& e = bends[b];
      const V4 alpha[3] = {Splat(e.alpha[0]), Splat(e.alpha[1]), Splat(e.alpha[2])};
      const V4 neg_lambda = Splat(-e.lambda_N_per_m);
      const V4 x2 = Load3<kAvx2>(xp + o2), v2 = Load3<kAvx2>(vp + o2);
      // 0 + w0 a0 + w1 a1 + w2 a2 (the 0 + as in the Eigen reference: it turns -0 into +0).
      const V4 r = Splat(0.0) + alpha[0] * x0 + alpha[1] * x1 + alpha[2] * x2;
      const V4 r_dot = Splat(0.0) + alpha[0] * v0 + alpha[1] * v1 + alpha[2] * v2;
      const V4 f = neg_lambda * (r + damping_s * r_dot);
      if (!distinct) {  // corner by corner through memory
        const int o[3] = {o0, o1, o2};
        HAPTEX_UNROLL
        for (int k = 0; k < 3; ++k) {
          Store3(Load3<kAvx2>(fp + o[k]) + alpha[k] * f, fp + o[k]);
          if constexpr (kDfv) {
            Store3(Load3<kAvx2>(dfv + o[k]) + alpha[k] * (neg_lambda * r_dot), dfv + o[k]);
          }
        }
        ++b;
        break;
      }
      f0 += alpha[0] * f;
      f1 += alpha[1] * f;
      V4 f2 = Load3<kAvx2>(fp + o2) + alpha[2] * f;
      Store3(f0, fp + o0);  // corner 0 is done: the chain moves on
      V4 d2{};
      if constexpr (kDfv) {
        const V4 kv = neg_lambda * r_dot;
        d0 += alpha[0] * kv;
        d1 += alpha[1] * kv;
        d2 = Load3<kAvx2>(dfv + o2) + alpha[2] * kv;
        Store3(d0, dfv + o0);
      }
      ++b;
      // The chain goes on if the next bend starts at corners 1 and 2 and ends at a new particle.
      const bool more = b < num_bends && 3 * bends[b].p[0] == o1 && 3 * bends[b].p[1] == o2 &&
                        3 * bends[b].p[2] != o1 && 3 * bends[b].p[2] != o2;
      if (!more) {
        Store3(f1, fp + o1);
        Store3(f2, fp + o2);
        if constexpr (kDfv) {
          Store3(d1, dfv + o1);
          Store3(d2, dfv + o2);
        }
        break;
      }
      o0 = o1, o1 = o2, o2 = 3 * bends[b].p[2];
      f0 = f1, f1 = f2;
      if constexpr (kDfv) d0 = d1, d1 = d2;
      x0 = x1, x1 = x2, v0 = v1, v1 = v2;
    }
  }
}

void AddBendingGeneric(const FabricModel& model, const double* x, const double* v, double* f, double* dfv) {
  if (dfv != nullptr) return BendingKernel<false, true>(model, x, v, f, dfv);
  BendingKernel<false, false>(model, x, v, f, dfv);
}

#ifdef HAPTEX_X86_KERNELS
__attribute__((target("avx2"), flatten)) void AddBendingAvx2(const FabricModel& model, const double* x, const double* v,
                                                             double* f, double* dfv) {
  if (dfv != nullptr) return BendingKernel<true, true>(model, x, v, f, dfv);
  BendingKernel<true, false>(model, x, v, f, dfv);
}
#endif

// Bending forces; the constant Jacobian blocks only when asked for.
void AddBending(const FabricModel& model, const Eigen::VectorXd& x, const Eigen::VectorXd& v, bool avx2,
                ForceSink* sink) {
  double* fp = sink->force_N->data();
  double* dfv = sink->wants_jacobians() ? sink->dfdx_v->data() : nullptr;
#ifdef HAPTEX_X86_KERNELS
  if (avx2) {
    AddBendingAvx2(model, x.data(), v.data(), fp, dfv);
  } else {
    AddBendingGeneric(model, x.data(), v.data(), fp, dfv);
  }
#else
  AddBendingGeneric(model, x.data(), v.data(), fp, dfv);
#endif
  if (sink->wants_jacobians() && !sink->constant_jacobians_added) AddBendingBlocks(model, sink);
}

// Linear drag's constant Jacobian blocks: -c0 A_p I per particle, scaled by the sink.
void AddLinearDragBlocks(const FabricModel& model, ForceSink* sink) {
  const double c0 = model.options.drag.linear_N_s_per_m3;
  if (!(c0 > 0.0)) return;
  std::vector<Eigen::Matrix3d>& system = *sink->system;
  for (int p = 0; p < model.num_particles; ++p) {
    system[static_cast<std::size_t>(model.pattern.diag_slot[static_cast<std::size_t>(p)])].diagonal().array() -=
        sink->dv_scale * c0 * model.area_m2[p];
  }
}

// Linear (viscous) drag -c A v (its Jacobian is constant) and the loads m g + external force
// (AddExternalForces) in one pass over the particles, added to each particle in that order.
void AddLinearDragAndLoads(const FabricModel& model, const FabricState& state, ForceSink* sink) {
  const double c0 = model.options.drag.linear_N_s_per_m3;
  const bool drag = c0 > 0.0;
  const Eigen::Vector3d& g = model.options.gravity_m_per_s2;
  const Xyz gravity = {V2{g.x(), g.y()}, g.z()};
  const double* vp = state.v_W_m_per_s.data();
  const double* load = state.external_force_W_N.data();
  // Model data in locals: the force stores could alias it, so it would be reloaded.
  const double* area = model.area_m2.data();
  const double* mass = model.mass_kg.data();
  const int n = model.num_particles;
  double* fp = sink->force_N->data();
  for (int p = 0; p < n; ++p) {
    double* fk = fp + 3 * p;
    Xyz f = LoadXyz(fk);
    if (drag) {
      const double c = c0 * area[p];
      const Xyz v = LoadXyz(vp + 3 * p);
      f = {f.xy - c * v.xy, f.z - c * v.z};
    }
    const double m = mass[p];
    const Xyz l = LoadXyz(load + 3 * p);
    f = {f.xy + (m * gravity.xy + l.xy), f.z + (m * gravity.z + l.z)};
    std::memcpy(fk, &f.xy, sizeof f.xy);
    fk[2] = f.z;
  }
  if (drag && sink->wants_jacobians() && !sink->constant_jacobians_added) AddLinearDragBlocks(model, sink);
}

}  // namespace

void AccumulateForces(const FabricModel& model, const FabricState& state, ForceSink* sink) {
  static const internal::ForceKernels kernels = internal::BestForceKernels();
  internal::AccumulateForces(model, state, kernels, sink);
}

internal::ForceKernels internal::BestForceKernels() {
  if (base::CpuHasAvx2() && base::CpuHasAvx512Vl()) return ForceKernels::kAvx2On32Registers;
  return base::CpuHasAvx2() ? ForceKernels::kAvx2 : ForceKernels::kPortable;
}

void internal::AccumulateForces(const FabricModel& model, const FabricState& state, ForceKernels kernels,
                                ForceSink* sink) {
  const Eigen::VectorXd& x = state.x_W_m;
  const Eigen::VectorXd& v = state.v_W_m_per_s;
  AddTriangleForces(model, x, v, kernels, sink);
  AddBending(model, x, v, kernels != ForceKernels::kPortable, sink);
  AddLinearDragAndLoads(model, state, sink);
}

void AddConstantJacobians(const FabricModel& model, ForceSink* sink) {
  AddBendingBlocks(model, sink);
  AddLinearDragBlocks(model, sink);
}

std::vector<std::array<std::uint8_t, 9>> internal::TriangleFirstBlocks(
    const std::vector<std::array<int, 9>>& triangle_slots, int num_blocks) {
  std::vector<std::array<std::uint8_t, 9>> first(triangle_slots.size(), std::array<std::uint8_t, 9>{});
  std::vector<unsigned char> seen(static_cast<std::size_t>(num_blocks), 0);
  for (std::size_t t0 = 0; t0 < triangle_slots.size(); t0 += kLanes) {
    const std::size_t end = std::min(t0 + kLanes, triangle_slots.size());
    for (int kl : kTriangleBlockOrder) {
      for (std::size_t t = t0; t < end; ++t) {
        const auto slot = static_cast<std::size_t>(triangle_slots[t][static_cast<std::size_t>(kl)]);
        if (seen[slot]) continue;
        seen[slot] = 1;
        first[t][static_cast<std::size_t>(kl)] = 1;
      }
    }
  }
  return first;
}

}  // namespace haptex::textile
