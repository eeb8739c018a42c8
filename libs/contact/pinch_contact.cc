#include "libs/contact/pinch_contact.h"

#include <algorithm>
#include <cmath>

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
      near_(static_cast<std::size_t>(patch.num_particles), 0),
      d2_thumb_(static_cast<std::size_t>(patch.num_particles), 0.0),
      d2_index_(static_cast<std::size_t>(patch.num_particles), 0.0),
      dist_thumb_(static_cast<std::size_t>(patch.num_particles), 0.0),
      dist_index_(static_cast<std::size_t>(patch.num_particles), 0.0),
      x_C_(3, patch.num_particles),
      touch_stamp_(static_cast<std::size_t>(patch.num_particles), 0),
      touch_k_(static_cast<std::size_t>(patch.num_particles), 0.0),
      touch_w_(static_cast<std::size_t>(patch.num_particles), 0.0),
      touch_kd_C_(Eigen::Matrix3Xd::Zero(3, patch.num_particles)) {
  // s^2 points per triangle: centroids of its s x s sub-triangles, the same in every triangle.
  const int s = options.pinch_samples_per_edge;
  double area_m2 = 0.0;
  for (const auto& t : patch.triangles) area_m2 += t.area_m2;
  if (!patch.triangles.empty()) {
    k_N_per_m_ = options.pad_stiffness_N_per_m3 * area_m2 /
                 static_cast<double>(patch.triangles.size() * static_cast<std::size_t>(s * s));
  }
  auto add = [&](double b1, double b2) { sample_w_.push_back({1.0 - b1 - b2, b1, b2}); };
  for (int i = 0; i < s; ++i) {
    for (int j = 0; i + j < s; ++j) {
      add((i + 1.0 / 3.0) / s, (j + 1.0 / 3.0) / s);
      if (i + j <= s - 2) add((i + 2.0 / 3.0) / s, (j + 2.0 / 3.0) / s);
    }
  }
  per_triangle_ = static_cast<int>(sample_w_.size());
  for (const auto& w : sample_w_) {
    full_wk_.push_back({w[0] * k_N_per_m_, w[1] * k_N_per_m_, w[2] * k_N_per_m_});
    for (std::size_t m = 0; m < 3; ++m) {
      full_kw_[m] += full_wk_.back()[m];
      full_ww_[m] += w[m];
    }
  }
  triangle_p_.reserve(patch.triangles.size());
  for (const auto& t : patch.triangles) triangle_p_.push_back(t.p);
  samples_.resize(patch.triangles.size() * sample_w_.size());
  triangle_held_.assign(patch.triangles.size(), 0);
  active_triangles_.reserve(patch.triangles.size());
  active_full_.reserve(patch.triangles.size());
  touched_.reserve(static_cast<std::size_t>(patch.num_particles));
}

void PinchContact::Reset() {
  if (maybe_active_) {
    for (auto& s : samples_) s.active = false;
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
    AxisC axis;
    axis.a = R_CW * (seg.a_W - origin_W_);
    axis.ab = R_CW * (seg.b_W - seg.a_W);
    const double len2 = axis.ab.squaredNorm();
    axis.inv_len2 = len2 > 0.0 ? 1.0 / len2 : 0.0;
    return axis;
  };
  axis_thumb_C_ = axis_in_c(seg_thumb_);
  axis_index_C_ = axis_in_c(seg_index_);

  // Forget the last tick's touched particles: a new stamp, and a particle's sums are zeroed
  // when first touched, so nothing is cleared here.
  if (++stamp_ == 0) {
    std::fill(touch_stamp_.begin(), touch_stamp_.end(), 0u);
    stamp_ = 1;
  }
  touched_.clear();

  // Particles: where they are in C, how far from each axis, which are near the intersection
  // (only their triangles can hold samples in it) and which lie in it (owned by the pinch).
  const double reach = std::min(radius_thumb_m_ + 0.5 * options_.thumb.length_m,
                                radius_index_m_ + 0.5 * options_.index.length_m);
  const double rt2 = radius_thumb_m_ * radius_thumb_m_, ri2 = radius_index_m_ * radius_index_m_;
  const int np = patch_.num_particles;
  for (int p = 0; p < np; ++p) {
    const std::size_t up = static_cast<std::size_t>(p);
    const Eigen::Vector3d x = state.x_W_m.segment<3>(3 * p);
    const Eigen::Vector3d rel = x - origin_W_;
    const Eigen::Vector3d x_C = R_CW * rel;
    x_C_.col(p) = x_C;
    const double dt2 = axis_thumb_C_.Distance2(x_C);
    const double di2 = axis_index_C_.Distance2(x_C);
    d2_thumb_[up] = dt2;
    d2_index_[up] = di2;
    dist_thumb_[up] = std::sqrt(dt2);
    dist_index_[up] = std::sqrt(di2);
    near_[up] = rel.squaredNorm() < reach * reach ? 1 : 0;
    if (!near_[up]) continue;
    if (dt2 < rt2 * (1.0 - kMargin) && di2 < ri2 * (1.0 - kMargin)) {
      (*owned)[up] = 1;
    } else if (!(dt2 > rt2 * (1.0 + kMargin) || di2 > ri2 * (1.0 + kMargin)) && InsideBoth(x)) {
      (*owned)[up] = 1;
    }
  }

  // Samples, a triangle at a time. A triangle with no near particle holds none; one whose
  // particles all lie deeper than the edge ramp in both fingers holds all at the full spring
  // (the distance to a capsule's axis is convex, so no point of the triangle is farther than
  // its farthest corner); one whose farthest corner is more than the triangle's diameter
  // outside a finger holds none (the distance changes no faster than the point moves).
  int num_active = 0;
  double weight_sum = 0.0;
  active_triangles_.clear();
  active_full_.clear();
  const double ramp = std::max(options_.pinch_edge_ramp_m, 0.0);
  const double full_t = radius_thumb_m_ - ramp, full_i = radius_index_m_ - ramp;
  const double full_t2 = full_t > 0.0 ? full_t * full_t * (1.0 - kMargin) : -1.0;
  const double full_i2 = full_i > 0.0 ? full_i * full_i * (1.0 - kMargin) : -1.0;
  const double out_t2 = rt2 * (1.0 + kMargin), out_i2 = ri2 * (1.0 + kMargin);
  // A sample whose convex bound (below) is under these passes the exact full-spring test
  // (dt2 < full_t2 and di2 < full_i2) whatever the rounding.
  const double full_t_sure = full_t > 0.0 ? full_t * (1.0 - kMargin) : -1.0;
  const double full_i_sure = full_i > 0.0 ? full_i * (1.0 - kMargin) : -1.0;
  const double k_full = k_N_per_m_;
  const int nt = static_cast<int>(triangle_p_.size());
  const int per = per_triangle_;
  // A triangle none of whose samples was active last tick has nothing to drop.
  auto drop_samples = [&](int t) {
    std::uint8_t& held = triangle_held_[static_cast<std::size_t>(t)];
    if (!held) return;
    held = 0;
    Sample* s = &samples_[static_cast<std::size_t>(t * per)];
    for (int j = 0; j < per; ++j) s[j].active = false;
  };
  for (int t = 0; t < nt; ++t) {
    const auto& p = triangle_p_[static_cast<std::size_t>(t)];
    Sample* s = &samples_[static_cast<std::size_t>(t * per)];
    const std::size_t p0 = static_cast<std::size_t>(p[0]), p1 = static_cast<std::size_t>(p[1]),
                      p2 = static_cast<std::size_t>(p[2]);
    if (!(near_[p0] || near_[p1] || near_[p2])) {
      drop_samples(t);
      continue;
    }
    const Eigen::Vector3d x0 = x_C_.col(p[0]), x1 = x_C_.col(p[1]), x2 = x_C_.col(p[2]);
    const double far_t2 = Max3(d2_thumb_[p0], d2_thumb_[p1], d2_thumb_[p2]);
    const double far_i2 = Max3(d2_index_[p0], d2_index_[p1], d2_index_[p2]);
    if (far_t2 < full_t2 && far_i2 < full_i2) {
      for (int j = 0; j < per; ++j) {
        Sample& smp = s[j];
        if (!smp.active) {
          // A new sample sticks where it meets the plane (paper: "initially static contact").
          const auto& w = sample_w_[static_cast<std::size_t>(j)];
          smp.ideal_C = (w[0] * x0 + w[1] * x1 + w[2] * x2).head<2>();
          smp.active = true;
          smp.sliding = false;
        }
        smp.k_N_per_m = k_full;
        weight_sum += k_full;
      }
      num_active += per;
      triangle_held_[static_cast<std::size_t>(t)] = 1;
      active_triangles_.push_back(t);
      active_full_.push_back(1);
    } else {
      const double diam = std::sqrt(Max3((x1 - x0).squaredNorm(), (x2 - x0).squaredNorm(),
                                         (x2 - x1).squaredNorm()));
      const double out_t = (radius_thumb_m_ + diam) * (1.0 + kMargin);
      const double out_i = (radius_index_m_ + diam) * (1.0 + kMargin);
      if (far_t2 > out_t * out_t || far_i2 > out_i * out_i) {
        drop_samples(t);
        continue;
      }
      const int active_before = num_active;
      bool all_full = true;
      const double dt_0 = dist_thumb_[p0], dt_1 = dist_thumb_[p1], dt_2 = dist_thumb_[p2];
      const double di_0 = dist_index_[p0], di_1 = dist_index_[p1], di_2 = dist_index_[p2];
      for (int j = 0; j < per; ++j) {
        Sample& smp = s[j];
        const auto& w = sample_w_[static_cast<std::size_t>(j)];
        // The distance to an axis is convex: at a sample it is at most the weighted distances
        // of the corners. Deep enough in both, the sample holds the full spring (no query).
        if (w[0] * dt_0 + w[1] * dt_1 + w[2] * dt_2 < full_t_sure &&
            w[0] * di_0 + w[1] * di_1 + w[2] * di_2 < full_i_sure) {
          if (!smp.active) {
            smp.ideal_C = (w[0] * x0 + w[1] * x1 + w[2] * x2).head<2>();
            smp.active = true;
            smp.sliding = false;
          }
          smp.k_N_per_m = k_full;
          weight_sum += k_full;
          ++num_active;
          continue;
        }
        const Eigen::Vector3d q_C = w[0] * x0 + w[1] * x1 + w[2] * x2;
        const double dt2 = axis_thumb_C_.Distance2(q_C);
        // Certainly outside the thumb: the index's distance cannot change that.
        const double di2 = dt2 > out_t2 ? 0.0 : axis_index_C_.Distance2(q_C);
        double k = k_full;  // deeper than the ramp in both: the full spring
        bool inside = !(dt2 > out_t2 || di2 > out_i2);  // else certainly outside a finger
        if (inside && !(dt2 < full_t2 && di2 < full_i2)) {
          // Near an edge: the depth in both decides.
          const double depth =
              std::min(radius_thumb_m_ - std::sqrt(dt2), radius_index_m_ - std::sqrt(di2));
          const double edge_ramp = options_.pinch_edge_ramp_m;
          inside = depth > 0.0;
          k = k_full * (edge_ramp > 0.0 ? std::min(1.0, depth / edge_ramp) : 1.0);
        }
        if (!inside) {
          smp.active = false;
          all_full = false;
          continue;
        }
        all_full = all_full && k == k_full;
        if (!smp.active) {
          smp.ideal_C = q_C.head<2>();
          smp.active = true;
          smp.sliding = false;
        }
        smp.k_N_per_m = k;
        weight_sum += k;
        ++num_active;
      }
      triangle_held_[static_cast<std::size_t>(t)] = num_active > active_before ? 1 : 0;
      if (num_active > active_before) {
        active_triangles_.push_back(t);
        active_full_.push_back(all_full ? 1 : 0);
      }
    }
  }
  num_active_ = num_active;
  weight_sum_ = weight_sum;
  active_ = num_active_ > 0;
  maybe_active_ = active_;
  if (!active_) return false;

  // Each sample's share of the grip is in proportion to its spring (full inside, ramped at the
  // edge). Coulomb's law for each sample (both faces grip: 2 mu), as UpdateStickSlip states it,
  // in C: the frictionless point is the sample projected onto the plane, (q_C.x, q_C.y).
  const double grip_per_stiffness = grip_N_ / weight_sum_;
  const double mu_s = 2.0 * mu.mu_static, mu_d = 2.0 * mu.mu_dynamic;
  // A sample at the full spring has the same load and limits as every other such sample.
  const double normal_full = grip_per_stiffness * k_full;
  const bool loaded_full = normal_full > 0.0 && k_full > 0.0;
  const double limit_full[2] = {mu_s * normal_full * (1.0 + 1e-9), mu_d * normal_full * (1.0 + 1e-9)};
  const double kk_full = k_full * k_full;
  double k_ideal_x = 0.0, k_ideal_y = 0.0;
  int num_sliding = 0;
  // Coulomb's law for a loaded sample at (qx, qy): sticks, or its ideal position trails the
  // frictionless point at mu_d of the load. Leaves the ideal position in (ix, iy).
  auto coulomb = [&](Sample& smp, double qx, double qy, double k, double kk, double limit,
                     double normal_N, double* ix, double* iy) __attribute__((always_inline)) {
    const double sx = qx - *ix, sy = qy - *iy;
    const double s2 = sx * sx + sy * sy;
    if (kk * s2 <= limit * limit) {
      smp.sliding = false;  // sticks: the ideal position stays
    } else {
      const double f = mu_d * normal_N / (k * std::sqrt(s2));
      *ix = qx - f * sx;
      *iy = qy - f * sy;
      smp.ideal_C = Eigen::Vector2d(*ix, *iy);
      smp.sliding = true;
    }
  };
  const std::size_t num_triangles = active_triangles_.size();
  for (std::size_t a = 0; a < num_triangles; ++a) {
    const int t = active_triangles_[a];
    const auto& p = triangle_p_[static_cast<std::size_t>(t)];
    const Eigen::Vector3d x0 = x_C_.col(p[0]), x1 = x_C_.col(p[1]), x2 = x_C_.col(p[2]);
    Sample* s = &samples_[static_cast<std::size_t>(t * per)];
    // Per corner m: sum of w k, of w, and of w k (anchor - q) in C.
    double kw0 = 0.0, kw1 = 0.0, kw2 = 0.0, ww0 = 0.0, ww1 = 0.0, ww2 = 0.0;
    double d0x = 0.0, d0y = 0.0, d0z = 0.0, d1x = 0.0, d1y = 0.0, d1z = 0.0, d2x = 0.0, d2y = 0.0,
           d2z = 0.0;
    // A sample's spring w_m k (anchor - q) onto the corners' sums; (dx, dy, dz) = anchor - q in
    // C: the spring pulls the sample to its ideal position on the plane.
    auto add_spring = [&](double wk0, double wk1, double wk2, double dx, double dy, double dz)
                          __attribute__((always_inline)) {
      d0x += wk0 * dx;
      d0y += wk0 * dy;
      d0z += wk0 * dz;
      d1x += wk1 * dx;
      d1y += wk1 * dy;
      d1z += wk1 * dz;
      d2x += wk2 * dx;
      d2y += wk2 * dy;
      d2z += wk2 * dz;
    };
    if (active_full_[a] && loaded_full) {
      // Every sample active at the full spring: its weights times k and the sums of w k and w
      // are constants.
      for (int j = 0; j < per; ++j) {
        Sample& smp = s[j];
        const auto& w = sample_w_[static_cast<std::size_t>(j)];
        const auto& wk = full_wk_[static_cast<std::size_t>(j)];
        const double qx = w[0] * x0.x() + w[1] * x1.x() + w[2] * x2.x();
        const double qy = w[0] * x0.y() + w[1] * x1.y() + w[2] * x2.y();
        const double qz = w[0] * x0.z() + w[1] * x1.z() + w[2] * x2.z();
        double ix = smp.ideal_C.x(), iy = smp.ideal_C.y();
        coulomb(smp, qx, qy, k_full, kk_full, limit_full[smp.sliding ? 1 : 0], normal_full, &ix, &iy);
        num_sliding += smp.sliding ? 1 : 0;
        k_ideal_x += k_full * ix;
        k_ideal_y += k_full * iy;
        add_spring(wk[0], wk[1], wk[2], ix - qx, iy - qy, -qz);
      }
      kw0 = full_kw_[0];
      kw1 = full_kw_[1];
      kw2 = full_kw_[2];
      ww0 = full_ww_[0];
      ww1 = full_ww_[1];
      ww2 = full_ww_[2];
    } else {
      for (int j = 0; j < per; ++j) {
        Sample& smp = s[j];
        if (!smp.active) continue;
        const auto& w = sample_w_[static_cast<std::size_t>(j)];
        const double qx = w[0] * x0.x() + w[1] * x1.x() + w[2] * x2.x();
        const double qy = w[0] * x0.y() + w[1] * x1.y() + w[2] * x2.y();
        const double qz = w[0] * x0.z() + w[1] * x1.z() + w[2] * x2.z();
        const double k = smp.k_N_per_m;
        const double normal_N = grip_per_stiffness * k;
        double ix = smp.ideal_C.x(), iy = smp.ideal_C.y();
        if (normal_N > 0.0 && k > 0.0) {
          coulomb(smp, qx, qy, k, k * k, (smp.sliding ? mu_d : mu_s) * normal_N * (1.0 + 1e-9),
                  normal_N, &ix, &iy);
        } else {
          ix = qx;  // no load, no friction
          iy = qy;
          smp.ideal_C = Eigen::Vector2d(ix, iy);
        }
        num_sliding += smp.sliding ? 1 : 0;
        k_ideal_x += k * ix;
        k_ideal_y += k * iy;
        const double wk0 = w[0] * k, wk1 = w[1] * k, wk2 = w[2] * k;
        kw0 += wk0;
        kw1 += wk1;
        kw2 += wk2;
        ww0 += w[0];
        ww1 += w[1];
        ww2 += w[2];
        add_spring(wk0, wk1, wk2, ix - qx, iy - qy, -qz);
      }
    }
    const double corner[3][5] = {{kw0, ww0, d0x, d0y, d0z}, {kw1, ww1, d1x, d1y, d1z}, {kw2, ww2, d2x, d2y, d2z}};
    for (std::size_t m = 0; m < 3; ++m) {
      const int pm = p[m];
      const std::size_t um = static_cast<std::size_t>(pm);
      double* kd = touch_kd_C_.col(pm).data();
      if (touch_stamp_[um] != stamp_) {  // first touch this tick: its sums start from 0
        touch_stamp_[um] = stamp_;
        touched_.push_back(pm);
        touch_k_[um] = touch_w_[um] = kd[0] = kd[1] = kd[2] = 0.0;
      }
      touch_k_[um] += corner[m][0];
      touch_w_[um] += corner[m][1];
      kd[0] += corner[m][2];
      kd[1] += corner[m][3];
      kd[2] += corner[m][4];
    }
  }
  k_ideal_C_ = Eigen::Vector2d(k_ideal_x, k_ideal_y);
  num_sliding_ = num_sliding;
  last_triangle_ = active_triangles_.back();
  // Lumped onto the particles: each sample's spring w k towards (its particle + anchor - q), so
  // a particle gets the sum of w k and the anchor that gives the same force now.
  for (int p : touched_) {
    const std::size_t up = static_cast<std::size_t>(p);
    if (state.mode[up] != textile::ParticleMode::kFree) continue;
    const double k = touch_k_[up];
    springs->AddMoment(p, k, k * state.x_W_m.segment<3>(3 * p) + R_WC_ * touch_kd_C_.col(p));
  }
  return true;
}

void PinchContact::Resolve(const textile::FabricState& state, const Eigen::MatrixX2d& rest_uv_m,
                           PinchResult* result) {
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
    kq += touch_k_[up] * (state.x_W_m.segment<3>(3 * p) - origin_W_);
    uv += touch_w_[up] * rest_uv_m.row(p).transpose();
    vel += touch_w_[up] * state.v_W_m_per_s.segment<3>(3 * p);
  }
  const Eigen::Vector3d n = R_WC_.col(2);
  const Eigen::Vector3d k_anchor = R_WC_.col(0) * k_ideal_C_.x() + R_WC_.col(1) * k_ideal_C_.y();
  result->fabric_force_W_N = k_anchor - kq;                   // sum k (anchor - q)
  result->friction_W_N = (kq - kq.dot(n) * n) - k_anchor;     // sum k (free - anchor)
  result->samples = num_active_;
  result->sliding_samples = num_sliding_;
  result->touch_triangle = last_triangle_;
  result->touch_uv_m = uv / result->samples;
  result->touch_velocity_W = vel / result->samples;
}

}  // namespace haptex::contact
