// Writes a seed corpus for the envelope fuzz target: one serialized Envelope (the part inside
// the framing) per body type. The target frames and signs each input itself.
//
// usage: make_envelope_seeds OUT_DIR

#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>

#include "haptex/v1/envelope.pb.h"

namespace {

void Write(const std::string& dir, const std::string& name, const std::string& bytes) {
  std::ofstream(dir + "/" + name, std::ios::binary) << bytes;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: " << argv[0] << " OUT_DIR\n";
    return 2;
  }
  const std::string dir = argv[1];
  std::filesystem::create_directories(dir);
  haptex::v1::Envelope e;
  e.set_version(1);
  e.set_session_id(7);
  e.set_sender("seed");
  e.set_sender_epoch(1);
  int sequence = 0;
  auto emit = [&](const std::string& name) {
    e.set_sequence(static_cast<std::uint64_t>(++sequence));
    Write(dir, name, e.SerializeAsString());
  };
  auto* f = e.mutable_finger_states()->add_fingers();
  f->set_finger(haptex::v1::FINGER_THUMB);
  f->mutable_position_w_m()->set_x(0.01);
  emit("finger_states");
  auto* m = e.mutable_force_model()->add_fingers();
  for (int i = 0; i < 9; ++i) m->add_stiffness_w_n_per_m(-100.0 * i);
  emit("force_model");
  auto* patch = e.mutable_local_patch();
  for (int i = 0; i < 20; ++i) {
    patch->add_particle_ids(static_cast<std::uint32_t>(i));
    for (int k = 0; k < 3; ++k) patch->add_position_w_m(0.001 * i);
    patch->add_is_border(i % 4 == 0);
  }
  for (int i = 0; i < 18; ++i) patch->add_triangles(static_cast<std::uint32_t>(i));
  emit("local_patch");
  e.mutable_patch_result()->add_external_force_w_n(1.0);
  emit("patch_result");
  e.mutable_touch_trace()->add_fingers()->set_normal_force_n(2.0);
  emit("touch_trace");
  auto* pins = e.mutable_pin_frame()->add_fingers();
  for (int i = 0; i < 24; ++i) pins->add_amplitude_40hz(0.1f * static_cast<float>(i % 10));
  emit("pin_frame");
  e.mutable_cloth_frame()->set_quantum_m(1e-6);
  e.mutable_cloth_frame()->add_position_q(500000);
  emit("cloth_frame");
  e.mutable_health()->add_counters()->set_name("dropped");
  emit("health");
  e.mutable_control()->set_command(haptex::v1::Control::COMMAND_SHUTDOWN);
  emit("control");
  e.mutable_net_probe()->set_padding(std::string(64, 'p'));
  emit("net_probe");
  std::cout << "wrote " << sequence << " seeds to " << dir << "\n";
  return 0;
}
