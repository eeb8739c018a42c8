#include "services/viewer/scene_view.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Geometry>

#include "libs/codec/message_conversion.h"
#include "libs/scene/cloth_setup.h"
#include "libs/scene/scene_defaults.h"

namespace haptex::viewer {
namespace {

void SetColor(foxglove::Color* c, double r, double g, double b, double a = 1.0) {
  c->set_r(r);
  c->set_g(g);
  c->set_b(b);
  c->set_a(a);
}

void SetPose(foxglove::Pose* pose, const Eigen::Vector3d& p, const Eigen::Quaterniond& q) {
  pose->mutable_position()->set_x(p.x());
  pose->mutable_position()->set_y(p.y());
  pose->mutable_position()->set_z(p.z());
  pose->mutable_orientation()->set_w(q.w());
  pose->mutable_orientation()->set_x(q.x());
  pose->mutable_orientation()->set_y(q.y());
  pose->mutable_orientation()->set_z(q.z());
}

void SetStamp(foxglove::SceneEntity* e, std::uint64_t time_ns) {
  e->mutable_timestamp()->set_seconds(static_cast<std::int64_t>(time_ns / 1000000000u));
  e->mutable_timestamp()->set_nanos(static_cast<std::int32_t>(time_ns % 1000000000u));
  e->set_frame_id("world");
}

Eigen::Vector3d Vec(const v1::Vec3& v) { return {v.x(), v.y(), v.z()}; }

}  // namespace

std::vector<std::uint32_t> StandParticles(const scene::LoadedScene& loaded) {
  std::vector<std::uint32_t> particles;
  try {
    for (const int p : scene::MakeClothSetup(loaded).fixed_particles)
      particles.push_back(static_cast<std::uint32_t>(p));
  } catch (const std::invalid_argument&) {
    particles.clear();
  }
  return particles;
}

SceneViewConfig SceneViewConfigFromScene(const scene::LoadedScene& loaded) {
  SceneViewConfig config;
  for (const v1::FingerSpec& f : loaded.scene.fingers()) {
    const int slot = codec::FingerSlot(f.finger());
    if (slot < 0) continue;
    const contact::FingerShape shape = scene::FingerShapeFromScene(f);
    config.fingers[static_cast<std::size_t>(slot)] = {shape.radius_m, shape.length_m};
  }
  config.fixed_particles = StandParticles(loaded);
  return config;
}

const foxglove::SceneUpdate& SceneView::Build(const std::vector<float>& cloth_W_m, std::uint32_t u, std::uint32_t v,
                                              const PatchGridRect& patch, const v1::FingerStates& fingers,
                                              const v1::ForceModel& forces, std::uint64_t time_ns) {
  if (update_.entities_size() == 0) {
    update_.add_entities()->set_id("cloth");
    update_.add_entities()->set_id("fingers");
    update_.mutable_entities(0)->add_triangles();
  }
  // the cloth: the points change every frame, the indices only with the grid
  foxglove::SceneEntity* cloth = update_.mutable_entities(0);
  SetStamp(cloth, time_ns);
  foxglove::TriangleListPrimitive* mesh = cloth->mutable_triangles(0);
  SetPose(mesh->mutable_pose(), Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity());
  const std::uint64_t n = std::min<std::uint64_t>(static_cast<std::uint64_t>(u) * v, cloth_W_m.size() / 3);
  if (u != indexed_u_ || v != indexed_v_) {
    mesh->clear_indices();
    for (std::uint32_t j = 0; j + 1 < v; ++j) {
      for (std::uint32_t i = 0; i + 1 < u; ++i) {
        const std::uint32_t a = i + u * j, b = a + 1, c = a + u, d = c + 1;
        for (std::uint32_t k : {a, c, b, b, c, d}) mesh->add_indices(k);
      }
    }
    indexed_u_ = u;
    indexed_v_ = v;
  }
  while (mesh->points_size() > static_cast<int>(n)) mesh->mutable_points()->RemoveLast();
  while (mesh->colors_size() > static_cast<int>(n)) mesh->mutable_colors()->RemoveLast();
  for (std::uint64_t k = 0; k < n; ++k) {
    const Eigen::Vector3d p(cloth_W_m[3 * k], cloth_W_m[3 * k + 1], cloth_W_m[3 * k + 2]);
    foxglove::Point3* point =
        static_cast<int>(k) < mesh->points_size() ? mesh->mutable_points(static_cast<int>(k)) : mesh->add_points();
    point->set_x(p.x());
    point->set_y(p.y());
    point->set_z(p.z());
    const bool in_patch = patch.Contains(static_cast<std::uint32_t>(k % u), static_cast<std::uint32_t>(k / u));
    foxglove::Color* color =
        static_cast<int>(k) < mesh->colors_size() ? mesh->mutable_colors(static_cast<int>(k)) : mesh->add_colors();
    // denim blue, the patch under a finger amber
    in_patch ? SetColor(color, 0.85, 0.62, 0.25) : SetColor(color, 0.22, 0.30, 0.52);
  }
  // the stand: a grey clamp on each particle it holds
  cloth->clear_cubes();
  for (const std::uint32_t k : config_.fixed_particles) {
    if (k >= n) continue;
    foxglove::CubePrimitive* clamp = cloth->add_cubes();
    SetPose(clamp->mutable_pose(), Eigen::Vector3d(cloth_W_m[3 * k], cloth_W_m[3 * k + 1], cloth_W_m[3 * k + 2]),
            Eigen::Quaterniond::Identity());
    clamp->mutable_size()->set_x(0.006);
    clamp->mutable_size()->set_y(0.006);
    clamp->mutable_size()->set_z(0.006);
    SetColor(clamp->mutable_color(), 0.54, 0.56, 0.60);
  }

  // the fingers: a capsule along the finger frame's x, and the force on it
  foxglove::SceneEntity* hands = update_.mutable_entities(1);
  SetStamp(hands, time_ns);
  hands->clear_cylinders();
  hands->clear_spheres();
  hands->clear_arrows();
  // the cylinder's axis is its pose's z: turn z onto the finger's x
  const Eigen::Quaterniond z_to_x(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()));
  for (const v1::FingerState& s : fingers.fingers()) {
    const int slot = codec::FingerSlot(s.finger());
    if (slot < 0) continue;
    const SceneViewConfig::Finger& shape = config_.fingers[static_cast<std::size_t>(slot)];
    const Eigen::Vector3d p = Vec(s.position_w_m());
    Eigen::Quaterniond q(s.orientation_wf().w(), s.orientation_wf().x(), s.orientation_wf().y(),
                         s.orientation_wf().z());
    if (!(q.norm() > 0.5) || !p.allFinite()) continue;  // not a pose: nothing drawn
    q.normalize();
    const double shade = slot == 0 ? 0.0 : 1.0;
    foxglove::CylinderPrimitive* body = hands->add_cylinders();
    SetPose(body->mutable_pose(), p, q * z_to_x);
    body->mutable_size()->set_x(2 * shape.radius_m);
    body->mutable_size()->set_y(2 * shape.radius_m);
    body->mutable_size()->set_z(shape.length_m);
    body->set_bottom_scale(1);
    body->set_top_scale(1);
    SetColor(body->mutable_color(), 0.88 - 0.44 * shade, 0.63, 0.44 + 0.44 * shade);
    for (const double end : {-0.5, 0.5}) {
      foxglove::SpherePrimitive* cap = hands->add_spheres();
      SetPose(cap->mutable_pose(), p + q * Eigen::Vector3d(end * shape.length_m, 0, 0), q);
      cap->mutable_size()->set_x(2 * shape.radius_m);
      cap->mutable_size()->set_y(2 * shape.radius_m);
      cap->mutable_size()->set_z(2 * shape.radius_m);
      SetColor(cap->mutable_color(), 0.88 - 0.44 * shade, 0.63, 0.44 + 0.44 * shade);
    }
    for (const v1::FingerForceModel& m : forces.fingers()) {
      if (m.finger() != s.finger()) continue;
      const Eigen::Vector3d f = Vec(m.f0_w_n());
      const double magnitude = f.norm();
      if (!(magnitude > 1e-3) || !std::isfinite(magnitude)) continue;
      foxglove::ArrowPrimitive* arrow = hands->add_arrows();
      // the arrow is along its pose's x: turn x onto the force
      SetPose(arrow->mutable_pose(), p, Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitX(), f / magnitude));
      const double length_m = magnitude * config_.arrow_m_per_N;
      arrow->set_shaft_length(0.75 * length_m);
      arrow->set_shaft_diameter(0.0015);
      arrow->set_head_length(0.25 * length_m);
      arrow->set_head_diameter(0.004);
      SetColor(arrow->mutable_color(), 1.0, 0.25, 0.25);
    }
  }
  return update_;
}

}  // namespace haptex::viewer
