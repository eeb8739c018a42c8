// A FoxgloveServer with known content, for clients that are not ours (foxglove_ws_client_test.mjs):
// starts on a free port, prints "port <n>", and publishes a haptex.v1.ClothFrame on /cloth and a
// foxglove.SceneUpdate on /scene at 30 Hz; one second in it adds /late, for the late advertisement.
// usage: foxglove_test_server [seconds (default 10)]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <thread>

#include "foxglove/SceneUpdate.pb.h"
#include "haptex/v1/cloth_frame.pb.h"
#include "libs/codec/cloth_positions.h"
#include "services/viewer/foxglove_server.h"

namespace {

using haptex::codec::FileDescriptorSetOf;
using haptex::viewer::FoxgloveServer;

// A 2 x 2 grid the client checks value by value (quantised to a micrometre as global_sim sends it).
constexpr double kPositions[] = {0.0, 0.0, 0.0, 0.5, 0.0, 0.0, 0.0, 0.25, 0.0, 0.5, 0.25, 0.125};

haptex::v1::ClothFrame ClothFrameOf(std::uint64_t index) {
  haptex::v1::ClothFrame frame;
  frame.set_frame_index(index);
  frame.set_sim_time_s(static_cast<double>(index) / 30.0);
  frame.set_particles_u(2);
  frame.set_particles_v(2);
  frame.set_chunk_count(1);
  haptex::codec::EncodeClothPositions(kPositions, 4, haptex::codec::kClothQuantumM, &frame);
  return frame;
}

foxglove::SceneUpdate SceneUpdateOf(std::uint64_t time_ns) {
  foxglove::SceneUpdate update;
  foxglove::SceneEntity* cloth = update.add_entities();
  cloth->mutable_timestamp()->set_seconds(static_cast<std::int64_t>(time_ns / 1'000'000'000U));
  cloth->mutable_timestamp()->set_nanos(static_cast<std::int32_t>(time_ns % 1'000'000'000U));
  cloth->set_frame_id("world");
  cloth->set_id("cloth");
  foxglove::TriangleListPrimitive* mesh = cloth->add_triangles();
  mesh->mutable_pose()->mutable_orientation()->set_w(1.0);
  for (int i = 0; i < 4; ++i) {
    foxglove::Point3* point = mesh->add_points();
    point->set_x(kPositions[3 * i]);
    point->set_y(kPositions[3 * i + 1]);
    point->set_z(kPositions[3 * i + 2]);
  }
  for (const std::uint32_t index : {0U, 1U, 2U, 1U, 3U, 2U}) mesh->add_indices(index);
  mesh->mutable_color()->set_r(0.25);
  mesh->mutable_color()->set_g(0.5);
  mesh->mutable_color()->set_b(0.75);
  mesh->mutable_color()->set_a(1.0);
  foxglove::ArrowPrimitive* force = cloth->add_arrows();
  force->mutable_pose()->mutable_position()->set_z(0.125);
  force->set_shaft_length(0.05);
  force->set_shaft_diameter(0.002);
  force->set_head_length(0.01);
  force->set_head_diameter(0.004);
  foxglove::SpherePrimitive* finger = cloth->add_spheres();
  finger->mutable_size()->set_x(0.016);
  finger->mutable_size()->set_y(0.016);
  finger->mutable_size()->set_z(0.016);
  return update;
}

std::uint64_t NowNs() {
  return static_cast<std::uint64_t>(
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch())
          .count());
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const double seconds = argc > 1 ? std::atof(argv[1]) : 10.0;
    FoxgloveServer::Options options;
    options.name = "haptex-test";
    FoxgloveServer server(options);
    const std::uint32_t cloth = server.AddChannel(
        {"/cloth", "haptex.v1.ClothFrame", FileDescriptorSetOf(haptex::v1::ClothFrame::descriptor())});
    const std::uint32_t scene =
        server.AddChannel({"/scene", "foxglove.SceneUpdate", FileDescriptorSetOf(foxglove::SceneUpdate::descriptor())});
    std::printf("port %u\n", static_cast<unsigned>(server.port()));
    std::fflush(stdout);

    const auto start = std::chrono::steady_clock::now();
    const auto period = std::chrono::microseconds(1'000'000 / 30);
    bool late_added = false;
    for (std::uint64_t tick = 0;; ++tick) {
      const auto due = start + tick * period;
      if (due - start > std::chrono::duration<double>(seconds)) break;
      std::this_thread::sleep_until(due);
      if (!late_added && due - start >= std::chrono::seconds(1)) {
        server.AddChannel({"/late", "haptex.v1.ClothFrame", FileDescriptorSetOf(haptex::v1::ClothFrame::descriptor())});
        late_added = true;
      }
      const std::uint64_t now_ns = NowNs();
      if (server.HasSubscribers(cloth)) server.Publish(cloth, now_ns, ClothFrameOf(tick).SerializeAsString());
      if (server.HasSubscribers(scene)) server.Publish(scene, now_ns, SceneUpdateOf(now_ns).SerializeAsString());
    }
    const FoxgloveServer::Counters counters = server.counters();
    std::printf("sent %llu dropped %llu bad %llu\n", static_cast<unsigned long long>(counters.messages_sent),
                static_cast<unsigned long long>(counters.messages_dropped_slow_client),
                static_cast<unsigned long long>(counters.client_messages_bad));
    return 0;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "foxglove_test_server: %s\n", error.what());
    return 1;
  }
}
