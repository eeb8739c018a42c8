#include "services/common/service_context.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdlib>
#include <iostream>
#include <limits>

#include "libs/base/clock.h"
#include "libs/flags/finite_number.h"
#include "libs/net/peer_names.h"
#include "libs/net/udp_address.h"
#include "libs/runtime/logging.h"
#include "libs/runtime/shutdown_signal.h"
#include "libs/scene/session_key_source.h"

namespace haptex::services {

ServiceContext::ServiceContext(std::string name, const ServiceOptions& options)
    : name_(std::move(name)),
      logger_(runtime::SetupLogging(name_, options.log_level, options.log_file)),
      health_(name_),
      start_ns_(base::SteadyNowNs()),
      stop_at_ns_(options.duration_s > 0 ? start_ns_ + static_cast<std::int64_t>(options.duration_s * 1e9)
                                         : std::numeric_limits<std::int64_t>::max()) {
  runtime::InstallShutdownHandlers();
  flusher_ = std::make_unique<runtime::LogFlusher>(&rt_log_, logger_);
  if (!options.scene_path.empty()) {
    const scene::FabricDatabase fabrics(scene::FabricDatabase::DefaultDirectory());
    scene_ = std::make_unique<scene::LoadedScene>(scene::LoadScene(options.scene_path, fabrics));
  }
  const net::SessionKey key = scene::LoadSessionKey(options.key_file);
  net::MessengerConfig config;
  config.bind_address = options.bind;
  config.identity = {name_, 0, options.session_id != 0 ? options.session_id : key.DerivedSessionId()};
  config.also_known_as = net::peer::AlsoKnownAs(name_);
  messenger_ = std::make_unique<net::Messenger>(key, config);
  for (const std::string& text : options.peers) {
    const auto [peer_name, address] = ParsePeer(text);
    peers_.emplace_back(peer_name, messenger_->AddPeer(peer_name, address));
  }
  dropped_counter_ = health_.AddCounter("datagrams_dropped");
  // one per reason, so a campaign (or a user chasing losses) can tell an attack from a bug
  dropped_by_reason_ =
      health_.AddCounterPerReason<net::DropReason, net::kDropReasonCount>("datagrams_dropped_", net::DropReasonName);
  kernel_dropped_counter_ = health_.AddCounter("datagrams_dropped_by_kernel");
  if (!options.record_path.empty()) {
    recorder_ = std::make_unique<EnvelopeRecorder>(options.record_path, name_, messenger_->identity().epoch,
                                                   messenger_->identity().session_id);
    record_dropped_counter_ = health_.AddCounter("record_dropped");
    record_write_errors_counter_ = health_.AddCounter("record_write_errors");
  }
  viewer_ = FindPeer(net::peer::kViewer);
  if (const auto launcher = FindPeer("launcher")) {
    health_publisher_ =
        std::make_unique<runtime::HealthPublisher>(&health_, messenger_.get(), *launcher, options.health_hz, start_ns_);
  }
  const int refused = runtime::ApplyRtOptions(options.rt, *logger_);
  (void)refused;  // each refusal is logged as a warning; the service runs on
  logger_->info("{} receiving on {}", name_, net::FormatUdpAddress(messenger_->local_endpoint()));
}

ServiceContext::~ServiceContext() = default;

std::optional<PeerId> ServiceContext::FindPeer(std::string_view name) const {
  for (const auto& [peer_name, id] : peers_) {
    if (peer_name == name) return id;
  }
  return std::nullopt;
}

PeerId ServiceContext::RequirePeer(std::string_view name) const {
  if (const auto id = FindPeer(name)) return *id;
  throw std::invalid_argument(name_ + " needs --peer " + std::string(name) + "=HOST:PORT");
}

bool ServiceContext::SendBody(PeerId peer, const google::protobuf::MessageLite& body, int body_field_number) {
  // The viewer only watches: what it gets are copies (FingerStates, ForceModel, ...), not recorded
  // twice, so the run's counts stay those of the haptic loops. A loop records what only the viewer
  // gets with Outbox::Record.
  if (recorder_ && peer != viewer_) recorder_->RecordBody(body, body_field_number, base::SteadyNowNs());
  return messenger_->SendBody(peer, body, body_field_number);
}

void ServiceContext::RecordBody(const google::protobuf::MessageLite& body, int body_field_number) {
  if (recorder_) recorder_->RecordBody(body, body_field_number, base::SteadyNowNs());
}

void ServiceContext::Tick(std::int64_t now_ns) {
  // the transport's counters are read only when Health goes out
  if (!health_publisher_ || !health_publisher_->Due(now_ns)) return;
  health_.SetCounter(dropped_counter_, messenger_->received().TotalDropped());
  for (std::size_t r = 1; r < net::kDropReasonCount; ++r) {
    health_.SetCounter(dropped_by_reason_[r], messenger_->received().Get(static_cast<net::DropReason>(r)));
  }
  health_.SetCounter(kernel_dropped_counter_, messenger_->kernel_drops());
  if (recorder_) {
    health_.SetCounter(record_dropped_counter_, recorder_->dropped());
    health_.SetCounter(record_write_errors_counter_, recorder_->write_errors());
  }
  if (!health_publisher_->MaybePublish(now_ns) || (!recorder_ && !viewer_)) return;
  // the Health just sent, rebuilt into the same message (no allocation)
  const v1::Health& health = health_.Build(static_cast<double>(now_ns - start_ns_) * 1e-9);
  if (recorder_) recorder_->Record(health, now_ns);
  if (viewer_) messenger_->Send(*viewer_, health);
}

ServiceContext::ControlResult ServiceContext::HandleControl(const v1::Envelope& envelope) {
  if (envelope.body_case() != v1::Envelope::kControl) return ControlResult::kNotControl;
  const v1::Control& control = envelope.control();
  if (!control.target_service().empty() && control.target_service() != name_) return ControlResult::kForOthers;
  last_command_ = control.command();
  if (control.command() == v1::Control::COMMAND_SHUTDOWN) shutdown_commanded_ = true;
  return ControlResult::kForUs;
}

bool ServiceContext::StopRequested(std::int64_t now_ns) const {
  return runtime::ShutdownRequested() || shutdown_commanded_ || now_ns >= stop_at_ns_;
}

int RunService(int argc, char** argv, const std::string& name, const std::string& description,
               const std::function<void(CLI::App&)>& add_own_options, const std::function<int(ServiceContext&)>& run) {
  std::string binary = "haptex-" + name;
  std::replace(binary.begin(), binary.end(), '_', '-');
  CLI::App app{description, binary};
  ServiceOptions options;
  AddServiceOptions(app, &options);
  if (add_own_options) add_own_options(app);
  flags::RefuseNonFiniteNumbers(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  try {
    ServiceContext context(name, options);
    const int code = run(context);
    context.log().info("{} stopped (exit {})", name, code);
    return code;
  } catch (const scene::TextProtoError& e) {
    std::cerr << app.get_name() << ": " << e.what() << "\n";
    return 2;
  } catch (const std::invalid_argument& e) {
    std::cerr << app.get_name() << ": " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << app.get_name() << ": " << e.what() << "\n";
    return 1;
  }
}

}  // namespace haptex::services
