#include "libs/contact/pinch_contact.h"

#include <algorithm>
#include <cmath>

#include "libs/base/cpu_features.h"
#include "libs/contact/coulomb_friction.h"
#include "libs/contact/finger_finger_contact.h"

namespace haptex::contact {
namespace {

// Relative margin of the fast classification: a squared distance (in C, no square root) this far
// from a threshold decides what the exact test would decide, whatever the rounding of either
// (both are accurate to ~1e-15 relative). Closer calls: a particle goes to DepthInBoth, a sample
// to its depth from the same squared distances; triangles are classified only with the margin.
constexpr double kMargin = 1e-9;

double Max3(double a, double b, double c) { return std::max(a, std::max(b, c)); }

// Per-particle arrays are padded to whole 4-particle lanes.
std::size_t PaddedCount(int n) { return 4 * ((static_cast<std::size_t>(n) + 3) / 4); }

}  // namespace

PinchContact::PinchContact(const textile::FabricModel& patch, const ContactOptions& options)
    : patch_(patch),
      options_(options),
      // Fabric touching a finger has its midsurface one half thickness off the skin, where that
      // finger's own contact holds it; one more half thickness of tolerance lets such fabric count
      // as squeezed. Without it the pinch was entered and lost up to 24 times while the index
      // closed slowly on fabric the thumb held (tests/contact/pinch_onset_test.cc).
      radius_thumb_m_(options.thumb.radius_m + 2.0 * options.fabric_half_thickness_m),
      radius_index_m_(options.index.radius_m + 2.0 * options.fabric_half_thickness_m),
      k_N_per_m_(0.0),
      near_(PaddedCount(patch.num_particles), 0),
      deep_(PaddedCount(patch.num_particles), 0),
      particle_owned_(PaddedCount(patch.num_particles), internal::PinchOwned::kNo),
      beyond_(PaddedCount(patch.num_particles), 0),
      d2_thumb_(PaddedCount(patch.num_particles), 0.0),
      d2_index_(PaddedCount(patch.num_particles), 0.0),
      x_C_(4 * PaddedCount(patch.num_particles), 0.0),
      touch_sums_(static_cast<std::size_t>(patch.num_particles)),
      touch_w_(static_cast<std::size_t>(patch.num_particles), 0.0) {
  // s^2 points per triangle: centroids of its s x s sub-triangles, the same in every triangle.
  const int s = options.pinch_samples_per_edge;
  double area_m2 = 0.0;
  for (const auto& t : patch.triangles) area_m2 += t.area_m2;
  if (!patch.triangles.empty()) {
    k_N_per_m_ = options.pad_stiffness_N_per_m3 * area_m2 /
                 static_cast<double>(patch.triangles.size() * static_cast<std::size_t>(s * s));
  }
  std::vector<std::array<double, 3>> sample_w;  // barycentric weights of sample j of any triangle
  auto add = [&](double b1, double b2) { sample_w.push_back({1.0 - b1 - b2, b1, b2}); };
  for (int i = 0; i < s; ++i) {
    for (int j = 0; i + j < s; ++j) {
      add((i + 1.0 / 3.0) / s, (j + 1.0 / 3.0) / s);
      if (i + j <= s - 2) add((i + 2.0 / 3.0) / s, (j + 2.0 / 3.0) / s);
    }
  }
  per_triangle_ = static_cast<int>(sample_w.size());
  const int chunks = (per_triangle_ + 3) / 4;
  lanes_per_triangle_ = 4 * chunks;
  lane_w_.assign(12 * static_cast<std::size_t>(chunks), 0.0);
  lane_k_full_.assign(4 * static_cast<std::size_t>(chunks), 0.0);
  w_sum_full_.assign(3, 0.0);
  for (int j = 0; j < per_triangle_; ++j) {
    const auto& w = sample_w[static_cast<std::size_t>(j)];
    const int c = j / 4, lane = j % 4;
    for (int m = 0; m < 3; ++m) {
      lane_w_[static_cast<std::size_t>(12 * c + 4 * m + lane)] = w[static_cast<std::size_t>(m)];
      w_sum_full_[static_cast<std::size_t>(m)] += w[static_cast<std::size_t>(m)];
    }
    lane_k_full_[static_cast<std::size_t>(4 * c + lane)] = k_N_per_m_;
  }
  lane_wk_full_.assign(lane_w_.size(), 0.0);
  for (std::size_t i = 0; i < lane_w_.size(); ++i) lane_wk_full_[i] = lane_w_[i] * lane_k_full_[4 * (i / 12) + i % 4];
  // Thresholds on squared distances in C, with the margin of the fast classification.
  const double rt2 = radius_thumb_m_ * radius_thumb_m_, ri2 = radius_index_m_ * radius_index_m_;
  const double reach =
      std::min(radius_thumb_m_ + 0.5 * options_.thumb.length_m, radius_index_m_ + 0.5 * options_.index.length_m);
  edge_ramp_m_ = std::max(options_.pinch_edge_ramp_m, 0.0);
  const double full_t = radius_thumb_m_ - edge_ramp_m_, full_i = radius_index_m_ - edge_ramp_m_;
  thresholds_.reach2_m2 = reach * reach;
  thresholds_.in_thumb2 = rt2 * (1.0 - kMargin);
  thresholds_.in_index2 = ri2 * (1.0 - kMargin);
  thresholds_.out_thumb2 = rt2 * (1.0 + kMargin);
  thresholds_.out_index2 = ri2 * (1.0 + kMargin);
  thresholds_.full_thumb2 = full_t > 0.0 ? full_t * full_t * (1.0 - kMargin) : -1.0;
  thresholds_.full_index2 = full_i > 0.0 ? full_i * full_i * (1.0 - kMargin) : -1.0;
  // For any e > 0, (r + d)^2 <= (1 + e) r^2 + (1 + 1 / e) d^2, tight at d = e r: e from the rest
  // triangles' size (any e is safe). The margin covers the rounding, as above.
  double largest_area_m2 = 0.0;
  for (const auto& t : patch.triangles) largest_area_m2 = std::max(largest_area_m2, t.area_m2);
  const double diam_m = 2.0 * std::sqrt(largest_area_m2);  // a right isosceles triangle's
  auto far = [&](double r, double* r2_part, double* diam_part) {
    const double e = diam_m / r > 0.0 && std::isfinite(diam_m / r) ? diam_m / r : 1.0;
    *r2_part = (1.0 + e) * r * r * (1.0 + kMargin);
    *diam_part = (1.0 + 1.0 / e) * (1.0 + kMargin);
  };
  far(radius_thumb_m_, &thresholds_.far_thumb_r2, &thresholds_.far_thumb_diam);
  far(radius_index_m_, &thresholds_.far_index_r2, &thresholds_.far_index_diam);
  avx2_ = base::CpuHasAvx2();
  triangle_p_.reserve(patch.triangles.size());
  for (const auto& t : patch.triangles) triangle_p_.push_back(t.p);
  const std::size_t lanes = patch.triangles.size() * static_cast<std::size_t>(lanes_per_triangle_);
  ideal_x_.assign(lanes, 0.0);
  ideal_y_.assign(lanes, 0.0);
  k_.assign(lanes, 0.0);
  sliding_.assign(lanes, 0);
  triangle_held_.assign(patch.triangles.size(), 0);
  active_triangles_.resize(patch.triangles.size());
  candidates_.resize(patch.triangles.size());
  candidate_unchanged_.resize(patch.triangles.size());
  classify_.resize(patch.triangles.size());
  classify_deep_.resize(patch.triangles.size());
  hold_.resize(patch.triangles.size());
  active_full_.resize(patch.triangles.size());
  touched_.reserve(static_cast<std::size_t>(patch.num_particles));
}

void PinchContact::Reset() {
  if (maybe_active_) {
    std::fill(k_.begin(), k_.end(), 0.0);
    std::fill(triangle_held_.begin(), triangle_held_.end(), std::uint8_t{0});
  }
  maybe_active_ = false;
  active_ = false;
  num_active_ = 0;
}

double PinchContact::DepthInBoth(const Eigen::Vector3d& q) const {
  const double dt = (q - ClosestPointOnSegment(seg_thumb_.a_W, seg_thumb_.b_W, q)).norm();
  if (dt >= radius_thumb_m_) return radius_thumb_m_ - dt;
  const double di = (q - ClosestPointOnSegment(seg_index_.a_W, seg_index_.b_W, q)).norm();
  return std::min(radius_thumb_m_ - dt, radius_index_m_ - di);
}

bool PinchContact::Prepare(const FingerPose& thumb, const FingerPose& index, double grip_N,
                           const FrictionCoefficients& mu, const textile::FabricState& state,
                           std::vector<std::uint8_t>* owned, AnchorAccumulator* springs) {
  seg_thumb_ = CapsuleSegment(options_.thumb, thumb);
  seg_index_ = CapsuleSegment(options_.index, index);
  Eigen::Vector3d n, ct, ci;
  FingerFingerContact::Gap(options_, thumb, index, &n, &ct, &ci);
  // Contact plane midway between the two skins along the normal.
  origin_W_ = 0.5 * ((ct + options_.thumb.radius_m * n) + (ci - options_.index.radius_m * n));
  Eigen::Vector3d e1 = thumb.R_WF.col(0) - thumb.R_WF.col(0).dot(n) * n;
  if (e1.norm() < 1e-6) e1 = n.unitOrthogonal();
  e1.normalize();
  R_WC_.col(0) = e1;
  R_WC_.col(1) = n.cross(e1);
  R_WC_.col(2) = n;
  grip_N_ = grip_N;
  const Eigen::Matrix3d R_CW = R_WC_.transpose();
  auto axis_in_c = [&](const Segment& seg) {
    internal::PinchAxis axis;
    const Eigen::Vector3d a = R_CW * (seg.a_W - origin_W_);
    const Eigen::Vector3d ab = R_CW * (seg.b_W - seg.a_W);
    for (int i = 0; i < 3; ++i) {
      axis.a[i] = a[i];
      axis.ab[i] = ab[i];
    }
    const double len2 = ab.squaredNorm();
    axis.inv_len2 = len2 > 0.0 ? 1.0 / len2 : 0.0;
    return axis;
  };
  axis_thumb_C_ = axis_in_c(seg_thumb_);
  axis_index_C_ = axis_in_c(seg_index_);
  LocateParticles(state, owned);
  if (!ClassifySamples()) return false;
  ApplyFriction(mu);
  LumpSprings(state, springs);
  return true;
}

void PinchContact::LocateParticles(const textile::FabricState& state, std::vector<std::uint8_t>* owned) {
  // Particles: where they are in C, how far from each axis, which are near the intersection
  // (only their triangles can hold samples in it) and which lie in it (owned by the pinch).
  internal::PinchLocateInput in;
  in.x_W_m = state.x_W_m.data();
  in.num_particles = patch_.num_particles;
  for (int i = 0; i < 3; ++i) {
    in.origin_W_m[i] = origin_W_[i];
    for (int j = 0; j < 3; ++j) in.R_CW[3 * i + j] = R_WC_(j, i);
  }
  in.thumb = axis_thumb_C_;
  in.index = axis_index_C_;
  in.reach2_m2 = thresholds_.reach2_m2;
  in.in_thumb2 = thresholds_.in_thumb2;
  in.in_index2 = thresholds_.in_index2;
  in.out_thumb2 = thresholds_.out_thumb2;
  in.out_index2 = thresholds_.out_index2;
  in.full_thumb2 = thresholds_.full_thumb2;
  in.full_index2 = thresholds_.full_index2;
  internal::LocatePinchParticles(in,
                                 {x_C_.data(), d2_thumb_.data(), d2_index_.data(), near_.data(), deep_.data(),
                                  particle_owned_.data(), beyond_.data()},
                                 avx2_);
  static_assert(kPinchBeyondThumbBit == 2 && kPinchBeyondIndexBit == 4);  // beyond_'s bits, shifted
  for (int p = 0; p < patch_.num_particles; ++p) {
    const std::size_t up = static_cast<std::size_t>(p);
    std::uint8_t bits = static_cast<std::uint8_t>(beyond_[up] << 1);
    if (particle_owned_[up] == internal::PinchOwned::kYes) bits |= kPinchOwnedBit;
    // Too close to call from the squared distances in C: the exact test.
    if (particle_owned_[up] == internal::PinchOwned::kExactTest && InsideBoth(state.x_W_m.segment<3>(3 * p))) {
      bits |= kPinchOwnedBit;
    }
    (*owned)[up] = bits;
  }
}

bool PinchContact::ClassifySamples() {
  if (!(k_N_per_m_ > 0.0)) {  // a patch without area: no sample can hold a spring
    active_ = maybe_active_ = false;
    num_active_ = 0;
    return false;
  }
  // A triangle with no near particle holds no sample; one whose farthest corner is more than the
  // triangle's diameter outside a finger holds none (the distance changes no faster than the
  // point moves); one whose corners all lie deeper than the edge ramp in both fingers holds all
  // at the full spring (the distance to a capsule's axis is convex), and if it did so last tick
  // too nothing changes; the rest are classified sample by sample.
  const double full_t2 = thresholds_.full_thumb2, full_i2 = thresholds_.full_index2;
  const int nt = static_cast<int>(triangle_p_.size());
  const std::size_t lanes = static_cast<std::size_t>(lanes_per_triangle_);
  constexpr auto kAllFull = static_cast<std::uint8_t>(internal::PinchTriangleHold::kAllFull);
  // Appended without branches: each entry is written, then kept or not.
  int* const candidate = candidates_.data();
  std::uint8_t* const unchanged = candidate_unchanged_.data();
  int* const classify = classify_.data();
  std::uint8_t* const classify_deep = classify_deep_.data();
  int num_candidates = 0, num_classify = 0;
  for (int t = 0; t < nt; ++t) {
    const auto& p = triangle_p_[static_cast<std::size_t>(t)];
    const std::size_t p0 = static_cast<std::size_t>(p[0]), p1 = static_cast<std::size_t>(p[1]),
                      p2 = static_cast<std::size_t>(p[2]);
    bool is_candidate = (near_[p0] | near_[p1] | near_[p2]) != 0;
    // Corner by corner (the particles' flags), not from the maxima: std::max drops a NaN, and a
    // NaN corner must not make its triangle deep (its samples would start at NaN points and
    // spread them).
    const bool deep = (deep_[p0] & deep_[p1] & deep_[p2]) != 0;
    if (is_candidate && !deep) {
      // (radius + diam)^2 <= far_*_r2 + far_*_diam diam^2 (thresholds_): no square root.
      const double far_t2 = Max3(d2_thumb_[p0], d2_thumb_[p1], d2_thumb_[p2]);
      const double far_i2 = Max3(d2_index_[p0], d2_index_[p1], d2_index_[p2]);
      const Eigen::Map<const Eigen::Vector4d> x0(&x_C_[4 * p0]), x1(&x_C_[4 * p1]), x2(&x_C_[4 * p2]);
      const double diam2 = Max3((x1 - x0).squaredNorm(), (x2 - x0).squaredNorm(), (x2 - x1).squaredNorm());
      is_candidate = !(far_t2 > thresholds_.far_thumb_r2 + thresholds_.far_thumb_diam * diam2 ||
                       far_i2 > thresholds_.far_index_r2 + thresholds_.far_index_diam * diam2);
    }
    std::uint8_t& held = triangle_held_[static_cast<std::size_t>(t)];
    if (is_candidate) {
      // Deep now and all at the full spring from the last tick: nothing for the kernel to change.
      const bool same = deep && held == kAllFull;
      candidate[num_candidates] = t;
      unchanged[num_candidates++] = same ? 1 : 0;
      classify[num_classify] = t;
      classify_deep[num_classify] = deep ? internal::kPinchDeep : internal::kPinchNotDeep;
      num_classify += same ? 0 : 1;
    } else if (held) {
      held = 0;
      std::fill_n(k_.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(t) * lanes), per_triangle_, 0.0);
    }
  }

  internal::PinchClassifyInput in;
  in.list = Triangles(classify, num_classify);
  in.deep = classify_deep;
  in.thumb = axis_thumb_C_;
  in.index = axis_index_C_;
  in.radius_thumb_m = radius_thumb_m_;
  in.radius_index_m = radius_index_m_;
  in.edge_ramp_m = edge_ramp_m_;
  in.full_thumb2 = full_t2;
  in.full_index2 = full_i2;
  in.out_thumb2 = thresholds_.out_thumb2;
  in.out_index2 = thresholds_.out_index2;
  internal::PinchClassifyTotals totals =
      internal::ClassifyPinchSamples(Layout(), in, SampleArrays(), hold_.data(), avx2_);
  totals.all_full_triangles += num_candidates - num_classify;  // the unchanged ones
  int* const active = active_triangles_.data();
  std::uint8_t* const active_full = active_full_.data();
  int num_active = 0, j = 0;  // j: entry of classify
  for (int e = 0; e < num_candidates; ++e) {
    const int t = candidate[e];
    active[num_active] = t;
    if (unchanged[e]) {  // still kAllFull
      active_full[num_active++] = 1;
      continue;
    }
    const internal::PinchTriangleHold hold = hold_[static_cast<std::size_t>(j++)];
    triangle_held_[static_cast<std::size_t>(t)] = static_cast<std::uint8_t>(hold);
    active_full[num_active] = hold == internal::PinchTriangleHold::kAllFull ? 1 : 0;
    num_active += hold == internal::PinchTriangleHold::kNone ? 0 : 1;
  }
  num_active_triangles_ = num_active;
  const int full_samples = totals.all_full_triangles * per_triangle_;
  num_active_ = totals.active_not_full + full_samples;
  weight_sum_ = totals.k_not_full_N_per_m + static_cast<double>(full_samples) * k_N_per_m_;
  active_ = num_active_ > 0;
  maybe_active_ = active_;
  return active_;
}

internal::PinchSampleLayout PinchContact::Layout() const {
  internal::PinchSampleLayout layout;
  layout.chunks = lanes_per_triangle_ / 4;
  layout.w = lane_w_.data();
  layout.k_full_lanes = lane_k_full_.data();
  layout.w_sum_full = w_sum_full_.data();
  layout.k_full_N_per_m = k_N_per_m_;
  layout.wk_full = lane_wk_full_.data();
  return layout;
}

internal::PinchTriangleList PinchContact::Triangles(const int* triangles, int num_triangles) const {
  return {x_C_.data(), triangle_p_.data(), triangles, num_triangles};
}

internal::PinchSampleArrays PinchContact::SampleArrays() {
  return {ideal_x_.data(), ideal_y_.data(), k_.data(), sliding_.data()};
}

void PinchContact::ApplyFriction(const FrictionCoefficients& mu) {
  // Each sample's share of the grip is in proportion to its spring (full inside, ramped at the
  // edge). Coulomb's law for each sample (both faces grip: 2 mu), as UpdateStickSlip states it,
  // in C: the frictionless point is the sample projected onto the plane, (q_C.x, q_C.y).
  // Only the particles the last sums touched (LumpSprings listed them) are not zero.
  for (int p : touched_) {
    touch_sums_[static_cast<std::size_t>(p)] = internal::PinchParticleSums{};
    touch_w_[static_cast<std::size_t>(p)] = 0.0;
  }
  internal::PinchFrictionInput in;
  in.list = Triangles(active_triangles_.data(), num_active_triangles_);
  in.full = active_full_.data();
  in.normal_per_stiffness_m = grip_N_ / weight_sum_;
  in.mu_static = 2.0 * mu.mu_static;
  in.mu_dynamic = 2.0 * mu.mu_dynamic;
  const internal::PinchFrictionTotals totals =
      internal::ApplyPinchFriction(Layout(), in, SampleArrays(), touch_sums_.data(), touch_w_.data(), avx2_);
  k_ideal_C_ = Eigen::Vector2d(totals.k_ideal_x_N, totals.k_ideal_y_N);
  num_sliding_ = totals.sliding;
  last_triangle_ = active_triangles_[static_cast<std::size_t>(num_active_triangles_ - 1)];
}

void PinchContact::LumpSprings(const textile::FabricState& state, AnchorAccumulator* springs) {
  // Lumped onto the particles: each sample's spring w k towards (its particle + anchor - q), so
  // a particle gets the sum of w k and the anchor that gives the same force now.
  touched_.clear();
  for (int p = 0; p < patch_.num_particles; ++p) {
    const std::size_t up = static_cast<std::size_t>(p);
    if (!(touch_w_[up] > 0.0)) continue;
    touched_.push_back(p);
    if (state.mode[up] != textile::ParticleMode::kFree) continue;
    const internal::PinchParticleSums& sum = touch_sums_[up];
    const double k = sum.k_N_per_m;
    springs->AddMoment(p, k,
                       k * state.x_W_m.segment<3>(3 * p) + R_WC_ * Eigen::Vector3d(sum.kd_x_N, sum.kd_y_N, sum.kd_z_N));
  }
}

void PinchContact::Resolve(const textile::FabricState& state, const Eigen::MatrixX2d& rest_uv_m, PinchResult* result) {
  *result = PinchResult{};
  result->active = active_;
  result->normal_W = R_WC_.col(2);
  if (!active_) return;
  result->grip_N = grip_N_;
  // Every sum over the samples is linear in the particles: sum_samples k q = sum_p (sum w k) x_p.
  Eigen::Vector3d kq = Eigen::Vector3d::Zero();  // sum k (q - origin)
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();
  Eigen::Vector3d vel = Eigen::Vector3d::Zero();
  for (int p : touched_) {
    const std::size_t up = static_cast<std::size_t>(p);
    kq += touch_sums_[up].k_N_per_m * (state.x_W_m.segment<3>(3 * p) - origin_W_);
    uv += touch_w_[up] * rest_uv_m.row(p).transpose();
    vel += touch_w_[up] * state.v_W_m_per_s.segment<3>(3 * p);
  }
  const Eigen::Vector3d n = R_WC_.col(2);
  const Eigen::Vector3d k_anchor = R_WC_.col(0) * k_ideal_C_.x() + R_WC_.col(1) * k_ideal_C_.y();
  result->fabric_force_W_N = k_anchor - kq;                // sum k (anchor - q)
  result->friction_W_N = (kq - kq.dot(n) * n) - k_anchor;  // sum k (free - anchor)
  result->samples = num_active_;
  result->sliding_samples = num_sliding_;
  result->touch_triangle = last_triangle_;
  result->touch_uv_m = uv / result->samples;
  result->touch_velocity_W = vel / result->samples;
}

}  // namespace haptex::contact
