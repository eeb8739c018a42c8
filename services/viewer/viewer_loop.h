#pragma once
// The viewer's work per frame, apart from sockets. Read: every message the services send the
// viewer (ClothFrame chunks, FingerStates, ForceModel, TouchTrace, PinFrame, Health) is passed on
// to the sink under its sender's topic; ClothFrame chunks are also assembled into the whole cloth.
// Update: at the frame rate, the newest whole cloth, the fingers as capsules and their forces as
// arrows go out as one foxglove.SceneUpdate (scene_view.h) for Foxglove's 3-D panel. The viewer
// only watches: nothing it does reaches a haptic loop.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "haptex/v1/envelope.pb.h"
#include "libs/runtime/health_reporter.h"
#include "services/viewer/scene_view.h"
#include "services/viewer/viewer_sink.h"

namespace haptex::viewer {

struct ViewerLoopConfig {
  double frame_hz = 30.0;               ///< SceneUpdates per second at most
  std::uint64_t epoch_at_start_ns = 0;  ///< the wall clock at t_s = 0, for log times
  SceneViewConfig scene;
};

class ViewerLoop final {
 public:
  /// Registers its counters with `health` (which must outlive the loop).
  ViewerLoop(const ViewerLoopConfig& config, ViewerSink* sink, runtime::HealthReporter* health);

  void Read(const v1::Envelope& envelope, double t_s);
  void Update(double t_s, double dt_s);
  template <class Outbox>
  void Write(Outbox&) {}  // the viewer sends nothing over UDP but its Health

  struct Counters {
    std::uint64_t messages_passed_on = 0, cloth_frames_whole = 0, cloth_chunks_bad = 0, scene_updates = 0,
                  messages_unknown_sender = 0;
  };
  const Counters& counters() const { return counters_; }
  /// The newest whole cloth [m, W], 3 per particle; empty before the first.
  const std::vector<float>& cloth_W_m() const { return cloth_W_m_; }
  /// The local patch of that cloth.
  const PatchGridRect& patch() const { return patch_; }

 private:
  const std::string& TopicOf(const v1::Envelope& envelope);
  std::uint64_t LogTimeNs(double t_s) const;
  void AssembleCloth(const v1::ClothFrame& chunk);
  void PublishCounters();

  ViewerLoopConfig config_;
  ViewerSink* sink_;
  runtime::HealthReporter* health_;
  struct Topic {
    std::string sender;
    int body = 0;
    std::string name;
  };
  std::vector<Topic> topics_;
  std::string unknown_topic_ = "/unknown";
  // the cloth being assembled and the newest whole one
  std::uint64_t assembling_frame_ = 0;
  std::uint64_t chunks_seen_ = 0;  ///< bit k: chunk k of the frame being assembled arrived
  std::uint32_t u_ = 0, v_ = 0;
  std::vector<float> assembling_W_m_, cloth_W_m_;
  PatchGridRect assembling_patch_, patch_;  ///< the local patch of the frame being assembled, the newest
  bool cloth_new_ = false;
  v1::FingerStates fingers_;
  v1::ForceModel forces_;
  double next_scene_s_ = 0;
  SceneView scene_view_;
  Counters counters_;
  struct CounterIds {
    runtime::HealthReporter::CounterId passed, whole, bad, scenes, unknown;
  } ids_{};
};

}  // namespace haptex::viewer
