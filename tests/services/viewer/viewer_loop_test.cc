#include "services/viewer/viewer_loop.h"

#include <gtest/gtest.h>

#include <map>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "libs/codec/cloth_positions.h"
#include "tests/support/wrap_envelope.h"

namespace haptex::viewer {
namespace {

struct Published {
  std::string topic, type;
  std::uint64_t time_ns;
};

class CapturingSink final : public ViewerSink {
 public:
  void Publish(std::string_view topic, const google::protobuf::Message& message, std::uint64_t time_ns) override {
    published.push_back({std::string(topic), std::string(message.GetDescriptor()->full_name()), time_ns});
    if (message.GetDescriptor() == foxglove::SceneUpdate::descriptor()) last_scene.CopyFrom(message);
  }
  std::vector<Published> published;
  foxglove::SceneUpdate last_scene;
};

template <class Body>
v1::Envelope From(const std::string& sender, const Body& body, std::uint64_t sequence) {
  v1::Envelope e = testing::WrapEnvelope(body, sequence);
  e.set_sender(sender);
  return e;
}

// A u x v cloth in `chunks` ClothFrame chunks, every coordinate of particle p = `value` + p (mod 1000).
std::vector<v1::ClothFrame> Cloth(std::uint32_t u, std::uint32_t v, int chunks, std::uint64_t frame, float value) {
  std::vector<v1::ClothFrame> out;
  const std::uint32_t n = u * v, per = (n + chunks - 1) / chunks;
  for (int c = 0; c < chunks; ++c) {
    v1::ClothFrame f;
    f.set_frame_index(frame);
    f.set_particles_u(u);
    f.set_particles_v(v);
    f.set_first_particle(c * per);
    f.set_chunk_index(static_cast<std::uint32_t>(c));
    f.set_chunk_count(static_cast<std::uint32_t>(chunks));
    std::vector<double> x_W_m;
    for (std::uint32_t p = c * per; p < std::min(n, (c + 1) * per); ++p) {
      x_W_m.insert(x_W_m.end(), 3, static_cast<double>(value) + static_cast<double>(p % 1000));
    }
    codec::EncodeClothPositions(x_W_m.data(), static_cast<int>(x_W_m.size() / 3), codec::kClothQuantumM, &f);
    out.push_back(f);
  }
  return out;
}

struct Fixture {
  CapturingSink sink;
  runtime::HealthReporter health{"viewer"};
  ViewerLoopConfig config = [] {
    ViewerLoopConfig c;
    c.frame_hz = 30;
    c.epoch_at_start_ns = 1'000'000'000;
    return c;
  }();
  ViewerLoop loop{config, &sink, &health};
};

TEST(ViewerLoopTest, PassesEachMessageOnUnderItsSendersTopic) {
  Fixture f;
  v1::FingerStates states;
  states.add_fingers()->set_finger(v1::FINGER_THUMB);
  v1::Health health;
  health.set_service("local_contact");
  f.loop.Read(From("device_bridge", states, 1), 0.5);
  f.loop.Read(From("local_contact", health, 1), 0.6);
  f.loop.Read(From("local_contact", v1::ForceModel{}, 2), 0.7);
  ASSERT_EQ(f.sink.published.size(), 3u);
  EXPECT_EQ(f.sink.published[0].topic, "/device_bridge/finger_states");
  EXPECT_EQ(f.sink.published[0].type, "haptex.v1.FingerStates");
  EXPECT_EQ(f.sink.published[0].time_ns, 1'500'000'000u);
  EXPECT_EQ(f.sink.published[1].topic, "/local_contact/health");
  EXPECT_EQ(f.sink.published[2].topic, "/local_contact/force_model");
  EXPECT_EQ(f.loop.counters().messages_passed_on, 3u);
}

TEST(ViewerLoopTest, ASenderNameThatIsNoServiceNameMakesNoTopic) {
  Fixture f;
  f.loop.Read(From("../../etc", v1::ForceModel{}, 1), 0.1);
  f.loop.Read(From("", v1::ForceModel{}, 2), 0.1);
  f.loop.Read(From(std::string(100, 'a'), v1::ForceModel{}, 3), 0.1);
  EXPECT_TRUE(f.sink.published.empty());
  EXPECT_EQ(f.loop.counters().messages_unknown_sender, 3u);
}

TEST(ViewerLoopTest, AssemblesTheClothFromChunksInAnyOrderAndSendsOneSceneAtTheFrameRate) {
  Fixture f;
  auto chunks = Cloth(5, 4, 3, 7, 0.5f);
  std::swap(chunks[0], chunks[2]);
  for (std::size_t c = 0; c < chunks.size(); ++c) {
    f.loop.Read(From("global_sim", chunks[c], c + 1), 0.1);
    if (c + 1 < chunks.size()) {
      EXPECT_TRUE(f.loop.cloth_W_m().empty()) << "a partial frame is not shown";
    }
  }
  ASSERT_EQ(f.loop.cloth_W_m().size(), 60u);
  EXPECT_FLOAT_EQ(f.loop.cloth_W_m()[3 * 19 + 2], 19.5f);
  f.loop.Update(0.1, 0.01);
  f.loop.Update(0.11, 0.01);  // nothing new: no second scene
  EXPECT_EQ(f.loop.counters().scene_updates, 1u);
  const foxglove::SceneUpdate& scene = f.sink.last_scene;
  ASSERT_EQ(scene.entities_size(), 2);
  const auto& mesh = scene.entities(0).triangles(0);
  EXPECT_EQ(mesh.points_size(), 20);
  EXPECT_EQ(mesh.indices_size(), 4 * 3 * 2 * 3);  // (u - 1)(v - 1) quads, two triangles each
  EXPECT_DOUBLE_EQ(mesh.points(19).z(), 19.5);
  for (const auto i : mesh.indices()) EXPECT_LT(i, 20u);

  // the next frame comes before the frame period is over: its scene waits for the period
  for (const auto& c : Cloth(5, 4, 3, 8, 1.5f)) f.loop.Read(From("global_sim", c, 9), 0.12);
  f.loop.Update(0.12, 0.01);
  EXPECT_EQ(f.loop.counters().scene_updates, 1u);
  f.loop.Update(0.1 + 1.0 / 30 + 1e-6, 0.01);
  EXPECT_EQ(f.loop.counters().scene_updates, 2u);
  EXPECT_DOUBLE_EQ(f.sink.last_scene.entities(0).triangles(0).points(19).z(), 20.5);
}

// The patch is the grid rectangle global_sim cut (amber), the rest denim; the stand's clamps sit on
// the particles it holds.
TEST(ViewerLoopTest, ThePatchGlobalSimCutIsColouredAndTheStandClampsItsParticles) {
  Fixture f;
  ViewerLoopConfig config = f.config;
  config.scene.fixed_particles = {0, 1, 2, 3, 4, 999};  // the top row of a 5 x 4 grid; 999 is none
  runtime::HealthReporter health{"viewer"};
  ViewerLoop loop{config, &f.sink, &health};
  auto chunks = Cloth(5, 4, 2, 1, 0.5f);
  for (auto& c : chunks) {
    c.set_patch_u_begin(1);
    c.set_patch_u_end(3);
    c.set_patch_v_begin(2);
    c.set_patch_v_end(4);
  }
  for (std::size_t c = 0; c < chunks.size(); ++c) loop.Read(From("global_sim", chunks[c], c + 1), 0.1);
  EXPECT_EQ(loop.patch().u_begin, 1u);
  EXPECT_EQ(loop.patch().v_end, 4u);
  loop.Update(0.1, 0.01);
  const foxglove::SceneEntity& cloth = f.sink.last_scene.entities(0);
  const auto& mesh = cloth.triangles(0);
  ASSERT_EQ(mesh.colors_size(), 20);
  std::vector<int> amber;
  for (int k = 0; k < 20; ++k) {
    if (mesh.colors(k).r() > 0.5) amber.push_back(k);
  }
  EXPECT_EQ(amber, (std::vector<int>{11, 12, 16, 17})) << "i_u in [1, 3), i_v in [2, 4) of a 5-wide grid";
  ASSERT_EQ(cloth.cubes_size(), 5);
  EXPECT_DOUBLE_EQ(cloth.cubes(3).pose().position().x(), 3.5);

  // a frame without a patch (no finger near): nothing amber
  for (const auto& c : Cloth(5, 4, 1, 2, 0.5f)) loop.Read(From("global_sim", c, 9), 0.2);
  loop.Update(0.2, 0.01);
  for (const auto& colour : f.sink.last_scene.entities(0).triangles(0).colors()) EXPECT_LT(colour.r(), 0.5);
}

TEST(ViewerLoopTest, TheLargestClothAScenesAllowsIsAssembledFromItsManyChunks) {
  Fixture f;
  const auto chunks = Cloth(401, 401, 42, 1, 0.0f);  // global_sim's 3900 particles per chunk
  for (std::size_t c = 0; c < chunks.size(); ++c) f.loop.Read(From("global_sim", chunks[c], c + 1), 0.1);
  EXPECT_EQ(f.loop.counters().cloth_chunks_bad, 0u);
  EXPECT_EQ(f.loop.counters().cloth_frames_whole, 1u);
  ASSERT_EQ(f.loop.cloth_W_m().size(), 3u * 401 * 401);
}

TEST(ViewerLoopTest, ChunksThatDoNotFitTheirGridAreCountedAndNotDrawn) {
  Fixture f;
  v1::ClothFrame too_far = Cloth(5, 4, 1, 1, 0)[0];
  too_far.set_first_particle(10);  // 20 particles from 10 overruns a 20-particle grid
  v1::ClothFrame ragged = Cloth(5, 4, 1, 2, 0)[0];
  ragged.add_position_q(1);  // not 3 per particle
  v1::ClothFrame no_step = Cloth(5, 4, 1, 5, 0)[0];
  no_step.set_quantum_m(0.0);
  v1::ClothFrame runaway = Cloth(5, 4, 1, 6, 0)[0];
  for (int i = 0; i < runaway.position_q_size(); ++i) runaway.set_position_q(i, 1 << 30);  // sums past the limit
  v1::ClothFrame huge = Cloth(5, 4, 1, 3, 0)[0];
  huge.set_particles_u(1u << 20);
  huge.set_particles_v(1u << 20);
  v1::ClothFrame bad_index = Cloth(5, 4, 1, 4, 0)[0];
  bad_index.set_chunk_index(1);
  for (const auto* chunk : {&too_far, &ragged, &huge, &bad_index, &no_step, &runaway}) {
    f.loop.Read(From("global_sim", *chunk, 1), 0.1);
  }
  EXPECT_EQ(f.loop.counters().cloth_chunks_bad, 6u);
  EXPECT_TRUE(f.loop.cloth_W_m().empty());
  f.loop.Update(1.0, 0.01);
  EXPECT_EQ(f.loop.counters().scene_updates, 0u);
}

TEST(ViewerLoopTest, FingersBecomeCapsulesAndTheirForcesArrows) {
  Fixture f;
  v1::FingerStates states;
  auto* thumb = states.add_fingers();
  thumb->set_finger(v1::FINGER_THUMB);
  thumb->mutable_position_w_m()->set_y(0.01);
  thumb->mutable_orientation_wf()->set_w(1);
  v1::ForceModel forces;
  auto* model = forces.add_fingers();
  model->set_finger(v1::FINGER_THUMB);
  model->mutable_f0_w_n()->set_y(-2.0);
  f.loop.Read(From("device_bridge", states, 1), 0.1);
  f.loop.Read(From("local_contact", forces, 1), 0.1);
  for (const auto& c : Cloth(3, 3, 1, 1, 0)) f.loop.Read(From("global_sim", c, 1), 0.1);
  f.loop.Update(0.2, 0.01);
  const auto& fingers = f.sink.last_scene.entities(1);
  ASSERT_EQ(fingers.cylinders_size(), 1);
  EXPECT_EQ(fingers.spheres_size(), 2);
  ASSERT_EQ(fingers.arrows_size(), 1);
  const auto& arrow = fingers.arrows(0);
  EXPECT_NEAR(arrow.shaft_length() + arrow.head_length(), 2.0 * 0.02, 1e-12);  // 2 N at 2 cm per newton
  // the arrow's x axis is turned onto -y: its quaternion rotates x to -y
  const auto& q = arrow.pose().orientation();
  const Eigen::Vector3d x_turned = Eigen::Quaterniond(q.w(), q.x(), q.y(), q.z()) * Eigen::Vector3d::UnitX();
  EXPECT_NEAR(x_turned.y(), -1.0, 1e-9);
}

}  // namespace
}  // namespace haptex::viewer
