#include "libs/contact/finger_fabric_contact.h"

#include <algorithm>

#include "libs/contact/coulomb_friction.h"

namespace haptex::contact {

FingerFabricContact::FingerFabricContact(const Eigen::VectorXd& particle_area_m2, const FingerShape& shape,
                                         const ContactOptions& options)
    : shape_(shape),
      radius_eff_m_(shape.radius_m + options.fabric_half_thickness_m),
      k_N_per_m_(options.pad_stiffness_N_per_m3 * particle_area_m2),
      particles_(static_cast<std::size_t>(particle_area_m2.size())),
      slot_particle_(static_cast<std::size_t>(particle_area_m2.size()), 0),
      slot_free_W_(3, particle_area_m2.size()),
      slot_spring_W_N_(3, particle_area_m2.size()),
      slot_ratio_(particle_area_m2.size()) {}

void FingerFabricContact::Reset() {
  law_load_ = FingerConeLoad{};
  if (!dirty_) return;  // an absent finger is reset every tick
  for (auto& c : particles_) c = ParticleContact{};
  dirty_ = false;
  slots_current_ = false;
}

int FingerFabricContact::num_active() const {
  int n = 0;
  for (const auto& c : particles_) n += c.active ? 1 : 0;
  return n;
}

void FingerFabricContact::Prepare(const FingerPose& pose, const textile::FabricState& state,
                                  const std::vector<std::uint8_t>& excluded, const FrictionCoefficients& mu,
                                  AnchorAccumulator* springs, std::uint8_t excluded_bits) {
  const Segment seg = CapsuleSegment(shape_, pose);
  const Eigen::Vector3d pad_normal = pose.R_WF.col(2);
  const double reach = radius_eff_m_ + 0.5 * shape_.length_m;
  // Squared distance to the axis without a square root or division; a particle more than a
  // relative 1e-9 outside needs no exact query (it would find depth <= 0).
  const Eigen::Vector3d ab = seg.b_W - seg.a_W;
  const double len2 = ab.squaredNorm();
  const double inv_len2 = len2 > 0.0 ? 1.0 / len2 : 0.0;
  const double outside2 = radius_eff_m_ * radius_eff_m_ * (1.0 + 1e-9);
  dirty_ = true;
  bool was_sliding = false;
  if (slots_current_) {
    was_sliding = num_slots_ > 0 && slots_sliding_;
  } else {
    for (const auto& c : particles_) {
      if (c.active && c.sliding) {
        was_sliding = true;
        break;
      }
    }
  }
  slots_current_ = false;  // until the slots below are complete

  // Contacts, with their held points carried along by the finger (the trial of a stick).
  Eigen::Vector3d normal_resultant_W_N = Eigen::Vector3d::Zero();
  Eigen::Vector3d friction_W_N = Eigen::Vector3d::Zero();
  int m = 0;
  const int n = static_cast<int>(particles_.size());
  // The scan over every particle, written out (Eigen's 3-vector code is several times longer).
  const std::uint8_t* skip = excluded.data();
  const textile::ParticleMode* mode = state.mode.data();
  const double* x_all = state.x_W_m.data();
  const double px = pose.p_W_m.x(), py = pose.p_W_m.y(), pz = pose.p_W_m.z();
  const double reach2 = reach * reach;
  for (int p = 0; p < n; ++p) {
    ParticleContact& c = particles_[static_cast<std::size_t>(p)];
    if ((skip[p] & excluded_bits) != 0 || mode[p] != textile::ParticleMode::kFree) {
      c.active = false;
      continue;
    }
    // Cheap rejects before the exact query: most particles are far from the finger.
    if (!c.active) {
      const double dx = x_all[3 * p] - px, dy = x_all[3 * p + 1] - py, dz = x_all[3 * p + 2] - pz;
      if ((dx * dx + dy * dy) + dz * dz >= reach2) continue;
    }
    const Eigen::Vector3d x = state.x_W_m.segment<3>(3 * p);
    const Eigen::Vector3d ax = x - seg.a_W;
    const double t = std::clamp(ax.dot(ab) * inv_len2, 0.0, 1.0);
    if ((ax - t * ab).squaredNorm() > outside2) {
      c.active = false;  // outside: no normal force, so no friction memory either
      continue;
    }
    const SurfaceQuery q = QueryCapsule(seg, radius_eff_m_, x, c.active ? c.normal_W : pad_normal);
    if (q.depth_m <= 0.0) {
      c.active = false;  // outside: no normal force, so no friction memory either
      continue;
    }
    if (!c.active) {
      // A new contact sticks where the particle meets the surface.
      c = ParticleContact{};
      c.active = true;
      c.anchor_W = q.surface_W;
    } else {
      c.anchor_W = pose.ToWorld(c.held_F);  // on the surface: the capsule moved with F
    }
    c.normal_W = q.normal_W;
    const double k = k_N_per_m_[p];
    const double normal_N = k * q.depth_m;
    const Eigen::Vector3d spring_W_N = k * (q.surface_W - c.anchor_W);
    const std::size_t j = static_cast<std::size_t>(m);
    slot_particle_[j] = p;
    slot_free_W_.col(m) = q.surface_W;
    slot_spring_W_N_.col(m) = spring_W_N;
    slot_ratio_[m] = spring_W_N.norm() / normal_N;
    normal_resultant_W_N += normal_N * q.normal_W;
    friction_W_N += spring_W_N;
    ++m;
  }

  // Coulomb's law for the finger: stick, break away at mu_s, slide at mu_d, stick again.
  const FingerConeLoad load = FingerCone(normal_resultant_W_N, friction_W_N);
  bool sliding = was_sliding;
  double mu_target = -1.0;  // < 0: the held points stay
  if (!(load.normal_N > 0.0)) {
    mu_target = 0.0;  // no normal force, no friction
  } else if (!was_sliding) {
    if (load.tangential_N > mu.mu_static * load.normal_N) {
      sliding = true;
      mu_target = mu.mu_static;  // the force breaks away at the static limit
    }
  } else if (load.tangential_N <= mu.mu_dynamic * load.normal_N * (1.0 + 1e-9)) {
    // Sliding needs no more than mu_d F^N: the motion stopped or turned. The relative tolerance
    // keeps a contact that slid to exactly mu_d F^N and stopped from sliding on through rounding.
    sliding = false;
  } else {
    mu_target = mu.mu_dynamic;
  }
  const double shared_mu = mu_target < 0.0 ? 0.0
                                           : SharedSlipCoefficient(normal_resultant_W_N, slot_spring_W_N_.leftCols(m),
                                                                   slot_ratio_.head(m), mu_target);

  Eigen::Vector3d held_friction_W_N = Eigen::Vector3d::Zero();  // what the law let the springs keep
  for (int j = 0; j < m; ++j) {
    const int p = slot_particle_[static_cast<std::size_t>(j)];
    ParticleContact& c = particles_[static_cast<std::size_t>(p)];
    const double ratio = slot_ratio_[j];
    const double keep = mu_target >= 0.0 && ratio > shared_mu ? shared_mu / ratio : 1.0;  // of its spring
    held_friction_W_N += keep * slot_spring_W_N_.col(j);
    if (keep < 1.0) {
      // Slide between the old and the desired point, and stay on the curved surface.
      const Eigen::Vector3d between = slot_free_W_.col(j) - (keep / k_N_per_m_[p]) * slot_spring_W_N_.col(j);
      c.anchor_W = ProjectOntoCapsule(seg, radius_eff_m_, between, c.normal_W);
    }
    c.held_F = pose.ToFinger(c.anchor_W);
    c.sliding = sliding;
    springs->Add(p, k_N_per_m_[p], c.anchor_W);
  }
  law_load_ = FingerCone(normal_resultant_W_N, held_friction_W_N);
  num_slots_ = m;
  slots_sliding_ = sliding;
  slots_current_ = true;
}

void FingerFabricContact::Resolve(const FingerPose& pose, const textile::FabricState& state,
                                  const Eigen::MatrixX2d& rest_uv_m, FingerFabricResult* result) {
  *result = FingerFabricResult{};
  const Segment seg = CapsuleSegment(shape_, pose);
  Eigen::Vector3d normal_acc = Eigen::Vector3d::Zero();
  Eigen::Vector2d uv_acc = Eigen::Vector2d::Zero();
  Eigen::Vector3d vel_acc = Eigen::Vector3d::Zero();
  double strongest = 0.0;
  // The active particles in increasing order: the last Prepare's slots where still current.
  const int n = slots_current_ ? num_slots_ : static_cast<int>(particles_.size());
  for (int i = 0; i < n; ++i) {
    const int p = slots_current_ ? slot_particle_[static_cast<std::size_t>(i)] : i;
    ParticleContact& c = particles_[static_cast<std::size_t>(p)];
    if (!c.active) continue;
    const Eigen::Vector3d x = state.x_W_m.segment<3>(3 * p);
    // The force as the implicit step applied it (action = reaction).
    result->force_W_N += k_N_per_m_[p] * (x - c.anchor_W);
    const SurfaceQuery q = QueryCapsule(seg, radius_eff_m_, x, c.normal_W);
    c.normal_N = k_N_per_m_[p] * std::max(0.0, q.depth_m);
    c.normal_W = q.normal_W;
    if (c.normal_N <= 0.0) continue;
    // Friction on the finger: the tangential spring pulls it towards the particle's side.
    result->friction_W_N += k_N_per_m_[p] * (q.surface_W - c.anchor_W);
    ++result->particles;
    result->normal_sum_N += c.normal_N;
    if (c.sliding) result->sliding_normal_N += c.normal_N;
    normal_acc += c.normal_N * q.normal_W;
    uv_acc += c.normal_N * rest_uv_m.row(p).transpose();
    vel_acc += c.normal_N * state.v_W_m_per_s.segment<3>(3 * p);
    if (c.normal_N > strongest) {
      strongest = c.normal_N;
      result->strongest_particle = p;
    }
  }
  if (result->normal_sum_N > 0.0) {
    const double norm = normal_acc.norm();
    if (norm > 0.0) result->normal_W = normal_acc / norm;
    result->touch_uv_m = uv_acc / result->normal_sum_N;
    result->touch_velocity_W = vel_acc / result->normal_sum_N;
    result->law_load = law_load_;
  }
}

}  // namespace haptex::contact
