#pragma once
// What every service process has: its name, logger, scene, authenticated messenger with named
// peers, Health to the launcher, Control handling and shutdown. It is the loops' Outbox: what a
// loop sends goes out through the messenger and, with --record, into the run's recording. The
// service's work lives in its loop object (services/<service>/<service>_loop.h); this class holds
// the wiring so each main stays thin.

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "libs/base/clock.h"
#include "libs/net/messenger.h"
#include "libs/runtime/health_publisher.h"
#include "libs/runtime/health_reporter.h"
#include "libs/runtime/rt_event_log.h"
#include "libs/scene/scene_loader.h"
#include "services/common/envelope_recorder.h"
#include "services/common/outbox.h"
#include "services/common/service_options.h"

namespace spdlog {
class logger;
}

namespace haptex::services {

class ServiceContext final : public Outbox {
 public:
  /// Sets up logging, loads the scene, the key and the messenger, and adds the peers. Throws
  /// std::invalid_argument (bad options) or scene::TextProtoError (bad scene).
  ServiceContext(std::string name, const ServiceOptions& options);
  ~ServiceContext();
  ServiceContext(const ServiceContext&) = delete;
  ServiceContext& operator=(const ServiceContext&) = delete;

  const std::string& name() const { return name_; }
  spdlog::logger& log() { return *logger_; }
  runtime::RtEventLog& rt_log() { return rt_log_; }
  net::Messenger& messenger() { return *messenger_; }
  /// The scene, or nullptr when none was given.
  const scene::LoadedScene* scene() const { return scene_.get(); }
  runtime::HealthReporter& health() { return health_; }
  /// The recorder of --record, or nullptr.
  EnvelopeRecorder* recorder() { return recorder_.get(); }

  std::optional<PeerId> FindPeer(std::string_view name) const;
  /// Throws std::invalid_argument naming the missing --peer.
  PeerId RequirePeer(std::string_view name) const;

  /// Call once per loop iteration: sends Health when due (no allocation once warmed up), with
  /// the messenger's dropped datagrams as `datagrams_dropped`.
  void Tick(std::int64_t now_ns);
  enum class ControlResult { kNotControl, kForOthers, kForUs };
  /// Handles a Control: kForUs when addressed to this service (or to all), which also records it
  /// as last_command() and stops the service for SHUTDOWN.
  ControlResult HandleControl(const v1::Envelope& envelope);
  /// A signal arrived, a Control SHUTDOWN came, or --duration has passed.
  bool StopRequested(std::int64_t now_ns) const;
  /// The last Control command received for us (COMMAND_UNSPECIFIED when none).
  v1::Control::Command last_command() const { return last_command_; }
  std::int64_t start_ns() const { return start_ns_; }
  /// Seconds from this service's start to `now_ns` (the steady clock): the loops' time base.
  double SecondsSinceStart(std::int64_t now_ns) const { return static_cast<double>(now_ns - start_ns_) * 1e-9; }

 protected:
  /// Sends `body` through the messenger and, with --record, records it (no allocation, no
  /// blocking): everything a service sends goes through here so that its run is recorded; what
  /// goes to the viewer is not (copies).
  bool SendBody(PeerId peer, const google::protobuf::MessageLite& body, int body_field_number) override;
  void RecordBody(const google::protobuf::MessageLite& body, int body_field_number) override;

 private:
  std::string name_;
  std::shared_ptr<spdlog::logger> logger_;
  runtime::RtEventLog rt_log_;
  std::unique_ptr<runtime::LogFlusher> flusher_;
  std::unique_ptr<scene::LoadedScene> scene_;
  std::unique_ptr<net::Messenger> messenger_;
  std::vector<std::pair<std::string, net::Messenger::PeerId>> peers_;
  runtime::HealthReporter health_;
  std::unique_ptr<runtime::HealthPublisher> health_publisher_;
  std::optional<PeerId> viewer_;  ///< also gets each Health (loop rates and overruns on the page)
  std::unique_ptr<EnvelopeRecorder> recorder_;
  runtime::HealthReporter::CounterId record_dropped_counter_ = 0;
  runtime::HealthReporter::CounterId record_write_errors_counter_ = 0;  // a full disk, ...: recordings/ is incomplete
  runtime::HealthReporter::CounterId dropped_counter_ = 0;              // datagrams the messenger dropped, every reason
  runtime::HealthReporter::CounterId kernel_dropped_counter_ = 0;       // dropped by the kernel: queue full
  std::array<runtime::HealthReporter::CounterId, net::kDropReasonCount> dropped_by_reason_{};  // [kNone] unused
  std::int64_t start_ns_;
  std::int64_t stop_at_ns_;
  bool shutdown_commanded_ = false;
  v1::Control::Command last_command_ = v1::Control::COMMAND_UNSPECIFIED;
};

/// Parses the command line (shared options plus the service's own), builds the context and runs
/// `run`. Exit codes: run's result; 2 for bad options, scene or key; 1 for other failures.
int RunService(int argc, char** argv, const std::string& name, const std::string& description,
               const std::function<void(CLI::App&)>& add_own_options, const std::function<int(ServiceContext&)>& run);

}  // namespace haptex::services
