#include "launch/supervisor.h"

#include <signal.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <thread>

#include "launch/child_process.h"
#include "libs/base/clock.h"
#include "libs/net/peer_names.h"
#include "libs/net/udp_address.h"
#include "libs/runtime/shutdown_signal.h"
#include "libs/scene/scene_stalls.h"

namespace haptex::launch {

struct Supervisor::Live {
  SupervisedService service;
  std::size_t record_index = 0;
  std::unique_ptr<ChildProcess> child;
  std::int64_t last_health_ns = 0;
  bool ready = false;
  bool was_ready = false;                   // has reported STATE_READY at least once
  bool degraded_reported = false;           // a "degraded" event is out, its "recovered" not yet
  bool stopped = false;                     // exited during the stop (not a failure)
  bool stalled = false;                     // stopped (SIGSTOP) by a stall on purpose
  std::int64_t silence_counts_from_ns = 0;  // a stall's grace: not found silent before this
};

struct Supervisor::LiveRelay {
  SupervisedRelay relay;
  std::string name;  // "relay A-B", in events and errors
  std::size_t record_index = 0;
  std::unique_ptr<ChildProcess> child;
  bool died = false;
};

struct Supervisor::LiveStall {
  SupervisedStall planned;
  std::string target;  // "local_contact", "all"
  std::size_t record_index = 0;
  bool started = false;
  bool ended = false;
  std::int64_t started_ns = 0;                              // after the SIGSTOPs
  std::vector<std::pair<Supervisor::Live*, pid_t>> paused;  // and the process of each it stopped
};

namespace {

using P = v1::ServicePlacement;

double Seconds(std::int64_t ns) { return static_cast<double>(ns) / 1e9; }

std::string Fixed(double value, int digits) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << value;
  return s.str();
}

// The last non-empty line of a service's log: usually why it stopped.
std::string LastLine(const std::string& path) {
  std::ifstream in(path);
  std::string line, last;
  while (std::getline(in, line)) {
    if (!line.empty()) last = line;
  }
  return last;
}

// A restarted service writes new files (recording, force log, pin log) beside the first ones, so
// what its earlier instance wrote is kept: NAME.pb, NAME.restart1.pb, ...
std::vector<std::string> ArgvForStart(std::vector<std::string> argv, std::size_t restarts) {
  if (restarts == 0) return argv;
  for (std::size_t i = 1; i + 1 < argv.size(); ++i) {
    if (argv[i] != "--record" && argv[i] != "--force-log" && argv[i] != "--log-csv") continue;
    std::string& path = argv[i + 1];
    const auto slash = path.rfind('/');
    const auto dot = path.rfind('.');
    const auto at = dot != std::string::npos && (slash == std::string::npos || dot > slash) ? dot : path.size();
    path.insert(at, ".restart" + std::to_string(restarts));
  }
  return argv;
}

// What a relay prints once both its sockets are bound (cli/relay_command.cc).
constexpr char kRelayListening[] = "relay: listening on";

bool FileHasFrom(const std::string& path, std::uintmax_t offset, const std::string& text) {
  std::ifstream in(path);
  in.seekg(static_cast<std::streamoff>(offset));
  const std::string content((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return content.find(text) != std::string::npos;
}

// A relay forwards bytes it cannot read: it gets no session key.
std::vector<std::string> WithoutKey(const std::vector<std::string>& env) {
  std::vector<std::string> out;
  for (const std::string& e : env) {
    if (e.rfind("HAPTEX_SESSION_KEY=", 0) != 0) out.push_back(e);
  }
  return out;
}

// A service's text for the terminal: at most one line of 200 bytes, without control characters
// (which would move the cursor or rewrite the status line).
std::string Printable(const std::string& text) {
  std::string out = text.substr(0, 200);
  for (char& c : out) {
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
  }
  return out;
}

std::string ShortState(v1::Health::State state) {
  switch (state) {
    case v1::Health::STATE_STARTING:
      return "starting";
    case v1::Health::STATE_READY:
      return "ok";
    case v1::Health::STATE_DEGRADED:
      return "DEGRADED";
    case v1::Health::STATE_STOPPING:
      return "stopping";
    case v1::Health::STATE_FAULT:
      return "FAULT";
    default:
      return "?";
  }
}

}  // namespace

Supervisor::Supervisor(SupervisorConfig config, const net::SessionKey& key, std::ostream& out)
    : config_(std::move(config)), out_(out) {
  net::MessengerConfig messenger;
  messenger.bind_address = config_.launcher.Bind();
  messenger.identity = {config_.identity, 0, key.DerivedSessionId()};
  // services address their own host's launcher by the peer name, whatever its identity (launcher@HOST)
  messenger.also_known_as = {std::string(net::peer::kLauncher)};
  messenger_ = std::make_unique<net::Messenger>(key, messenger);
}

Supervisor::~Supervisor() = default;

double Supervisor::Now() const { return static_cast<double>(base::SteadyNowNs() - start_ns_) * 1e-9; }

void Supervisor::Event(const std::string& service, const std::string& kind, const std::string& detail) {
  record_->events.push_back({Now(), service, kind, detail});
  if (config_.status_in_place) out_ << "\r\x1b[K";
  out_ << "[" << Fixed(Now(), 2) << " s] " << (service.empty() ? "" : service + ": ") << kind
       << (detail.empty() ? "" : " (" + detail + ")") << std::endl;
}

void Supervisor::DrainHealth() {
  const auto handle = [this](const v1::Envelope& e, const net::Messenger::Endpoint&) {
    if (!e.has_health()) return;
    for (auto& live : live_) {
      if (Spec(live->service.placed.service.kind).name != e.health().service()) continue;
      // Health of an earlier instance (before a restart) is not this one's
      if (!live->child || static_cast<pid_t>(e.health().pid()) != live->child->pid()) return;
      live->last_health_ns = base::SteadyNowNs();
      auto& last = record_->services[live->record_index].last_health;
      // a service that degrades after it was ready (not while it waits for its device at start-up), or
      // recovers from that, says so in the event log, with its reason
      const v1::Health::State state = e.health().state();
      if (state == v1::Health::STATE_DEGRADED && live->was_ready && !live->degraded_reported) {
        Event(e.health().service(), "degraded", Printable(e.health().last_error()));
        live->degraded_reported = true;
      } else if (state == v1::Health::STATE_READY) {
        if (live->degraded_reported) Event(e.health().service(), "recovered", "");
        live->was_ready = true;
        live->degraded_reported = false;
      }
      last = e.health();
      if (e.health().state() == v1::Health::STATE_READY || e.health().state() == v1::Health::STATE_DEGRADED) {
        live->ready = true;
      }
      return;
    }
  };
  while (messenger_->Drain(handle) > 0) {
  }
}

void Supervisor::SendControl(v1::Control::Command command, const std::string& target_address, const std::string& target,
                             const std::string& reason) {
  v1::Control control;
  control.set_command(command);
  control.set_target_service(target);
  control.set_reason(reason);
  try {
    const auto to = net::ResolveUdpAddress(target_address);
    // UDP: a second copy covers a lost datagram; the commands are idempotent
    messenger_->SendTo(to, target, control);
    messenger_->SendTo(to, target, control);
  } catch (const std::exception& e) {
    record_->errors.push_back("cannot send " + v1::Control::Command_Name(command) + " to " + target + ": " + e.what());
  }
}

void Supervisor::HoldZeroForce(bool hold, const std::string& reason) {
  if (config_.bridge_address.empty()) return;
  SendControl(hold ? v1::Control::COMMAND_ZERO_FORCE : v1::Control::COMMAND_ENABLE_FORCE, config_.bridge_address,
              "device_bridge", reason);
  Event("device_bridge", hold ? "zero_force" : "enable_force", reason);
}

bool Supervisor::Start(Live& live) {
  ServiceRecord& record = record_->services[live.record_index];
  live.ready = false;
  live.stalled = false;  // a new process: no stall has stopped it
  live.child.reset();
  try {
    const int priority = config_.rt_priority > 0
                             ? FifoPriorityFor(config_.rt_priority, Spec(live.service.placed.service.kind).rt_rank)
                             : 0;
    live.child = std::make_unique<ChildProcess>(ArgvForStart(live.service.argv, record.pids.size()), config_.child_env,
                                                live.service.log_path, priority);
  } catch (const std::exception& e) {
    record_->errors.push_back(std::string(Spec(live.service.placed.service.kind).name) + ": " + e.what());
    return false;
  }
  live.last_health_ns = base::SteadyNowNs();
  record.pids.push_back(live.child->pid());
  Event(std::string(Spec(live.service.placed.service.kind).name), "started",
        "pid " + std::to_string(live.child->pid()) + ", " + live.service.placed.haptex.Peer());
  return true;
}

bool Supervisor::WaitReady(Live& live) {
  const std::string name(Spec(live.service.placed.service.kind).name);
  const std::int64_t deadline = base::SteadyNowNs() + static_cast<std::int64_t>(config_.ready_timeout_s * 1e9);
  while (true) {
    messenger_->WaitReadable(std::chrono::milliseconds(10));
    DrainHealth();
    EndStalls();  // a restart during a stall does not lengthen it
    if (live.ready) {
      Event(name, "ready", "");
      return true;
    }
    if (live.child->Poll()) {
      record_->services[live.record_index].exit = live.child->exit_text();
      record_->errors.push_back(name + " ended while starting (" + live.child->exit_text() +
                                "): " + LastLine(live.service.log_path) + " [" + live.service.log_path + "]");
      return false;
    }
    if (runtime::ShutdownRequested()) return false;
    if (base::SteadyNowNs() > deadline) {
      record_->errors.push_back(name + " sent no healthy Health within " + Fixed(config_.ready_timeout_s, 0) +
                                " s; see " + live.service.log_path);
      live.child->Signal(SIGKILL);
      while (!live.child->Poll()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
      return false;
    }
  }
}

bool Supervisor::Restart(Live& live, const std::string& how) {
  const std::string name(Spec(live.service.placed.service.kind).name);
  ServiceRecord& record = record_->services[live.record_index];
  record.exit = how;
  Event(name, "died", how);
  const double died_at = Now();
  const bool is_bridge = live.service.placed.service.kind == P::SERVICE_DEVICE_BRIDGE;
  // the device stays at zero force while a model restarts (a dead bridge: the controller's own
  // watchdog zeroes the device)
  if (!is_bridge) HoldZeroForce(true, "restarting " + name);
  while (record.restarts < config_.max_restarts) {
    ++record.restarts;
    if (Start(live) && WaitReady(live)) {
      record.restart_s = Now() - died_at;
      Event(name, "restarted", "after " + how + ", ready " + Fixed(record.restart_s, 3) + " s after it died");
      if (!is_bridge) HoldZeroForce(false, name + " is back");
      return true;
    }
    if (runtime::ShutdownRequested()) return false;
  }
  record_->errors.push_back(name + " failed " + std::to_string(config_.max_restarts) + " restarts; the run stops");
  return false;
}

bool Supervisor::StartRelay(LiveRelay& relay) {
  RelayRecord& record = record_->relays[relay.record_index];
  const std::string& log_path = relay.relay.log_path;
  std::error_code error;
  const std::uintmax_t log_size = std::filesystem::file_size(log_path, error);  // an earlier run's lines
  const std::uintmax_t from = error ? 0 : log_size;
  try {
    const int priority = config_.rt_priority > 0 ? FifoPriorityFor(config_.rt_priority, kRelayRtRank) : 0;
    relay.child = std::make_unique<ChildProcess>(relay.relay.argv, WithoutKey(config_.child_env), log_path, priority);
  } catch (const std::exception& e) {
    record_->errors.push_back(relay.name + ": " + e.what());
    return false;
  }
  record.pid = relay.child->pid();
  Event(relay.name, "started",
        "pid " + std::to_string(record.pid) + ", " + std::string(Spec(relay.relay.placed.a).name) + " sends to " +
            relay.relay.placed.listen.Peer() + ", " + std::string(Spec(relay.relay.placed.b).name) + " to " +
            relay.relay.placed.upstream.Peer());
  const std::int64_t deadline = base::SteadyNowNs() + static_cast<std::int64_t>(config_.ready_timeout_s * 1e9);
  while (true) {
    if (FileHasFrom(log_path, from, kRelayListening)) {
      Event(relay.name, "ready", "");
      return true;
    }
    if (relay.child->Poll()) {
      record.exit = relay.child->exit_text();
      record_->errors.push_back(relay.name + " ended while starting (" + record.exit + "): " + LastLine(log_path) +
                                " [" + log_path + "]");
      return false;
    }
    if (runtime::ShutdownRequested()) return false;
    if (base::SteadyNowNs() > deadline) {
      record_->errors.push_back(relay.name + " did not bind its sockets within " + Fixed(config_.ready_timeout_s, 0) +
                                " s; see " + log_path);
      relay.child->Signal(SIGKILL);
      while (!relay.child->Poll()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
      record.exit = relay.child->exit_text();
      return false;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
}

void Supervisor::CheckRelays() {
  for (auto& relay : relays_) {
    if (relay->died || !relay->child || !relay->child->Poll()) continue;
    // Not restarted: its report would start again from zero. The services' watchdogs keep the
    // device safe while the link is cut.
    relay->died = true;
    relay_died_ = true;
    RelayRecord& record = record_->relays[relay->record_index];
    record.exit = relay->child->exit_text();
    Event(relay->name, "died", record.exit);
    record_->errors.push_back(relay->name + " died (" + record.exit + "): the link is cut from then on; " +
                              LastLine(relay->relay.log_path) + " [" + relay->relay.log_path + "]");
  }
}

void Supervisor::StopRelays() {
  for (auto& relay : relays_) {
    if (!relay->child) continue;
    RelayRecord& record = record_->relays[relay->record_index];
    if (relay->child->Poll()) {
      if (record.exit.empty()) record.exit = relay->child->exit_text();
      continue;
    }
    // SIGTERM: the relay stops relaying and writes its report
    relay->child->Signal(SIGTERM);
    const auto wait_exit = [&](double seconds) {
      const std::int64_t until = base::SteadyNowNs() + static_cast<std::int64_t>(seconds * 1e9);
      while (base::SteadyNowNs() < until) {
        if (relay->child->Poll()) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
      }
      return relay->child->Poll();
    };
    std::string how = "after SIGTERM";
    if (!wait_exit(config_.stop_timeout_s)) {
      relay->child->Signal(SIGKILL);
      how = "after SIGKILL";
      wait_exit(5.0);
    }
    record.exit = relay->child->exit_text();
    Event(relay->name, "stopped", record.exit + " " + how);
  }
}

namespace {

bool StallPauses(const v1::Stall& stall, ServiceKind kind) {
  return stall.all() ? kind != P::SERVICE_VIEWER : kind == stall.service();
}

}  // namespace

void Supervisor::StartDueStalls() {
  const double since_start_s = Seconds(base::SteadyNowNs() - run_start_ns_);
  for (LiveStall& stall : stalls_) {
    if (stall.started || since_start_s < stall.planned.stall.at_s()) continue;
    stall.started = true;
    StallRecord& record = record_->stalls[stall.record_index];
    std::string pids;
    for (auto& live : live_) {
      // exited() without a Poll: a death not yet seen is the supervise loop's to handle, as ever
      if (!StallPauses(stall.planned.stall, live->service.placed.service.kind) || !live->child ||
          live->child->exited()) {
        continue;
      }
      live->child->Signal(SIGSTOP);
      live->stalled = true;
      stall.paused.push_back({live.get(), live->child->pid()});
      record.pids.push_back(live->child->pid());
      pids += (pids.empty() ? "pid " : ", ") + std::to_string(live->child->pid());
    }
    stall.started_ns = base::SteadyNowNs();
    const std::string planned = "planned at " + Fixed(stall.planned.stall.at_s(), 3) + " s for " +
                                Fixed(stall.planned.stall.duration_s(), 3) + " s";
    if (stall.paused.empty()) {
      stall.ended = true;
      record.note = "no process of it was running at its time";
      Event(stall.target, "stall_missed", planned + "; " + record.note);
      continue;
    }
    record.started_s = Seconds(stall.started_ns - run_start_ns_);
    Event(stall.target, "stall", planned + "; paused at " + Fixed(*record.started_s, 3) + " s (" + pids + ")");
  }
}

void Supervisor::EndStalls(const std::string& reason) {
  const std::int64_t grace_ns = static_cast<std::int64_t>(config_.stall_grace_s * 1e9);
  for (LiveStall& stall : stalls_) {
    if (!stall.started || stall.ended) continue;
    // measured before the first SIGCONT (and started after the last SIGSTOP): each process paused
    // at least paused_s, and paused_s >= duration_s unless the run stops first
    const std::int64_t now = base::SteadyNowNs();
    const double paused_s = Seconds(now - stall.started_ns);
    const bool due = paused_s >= stall.planned.stall.duration_s();
    if (!due && reason.empty()) continue;
    stall.ended = true;
    StallRecord& record = record_->stalls[stall.record_index];
    std::string gone;
    for (auto& [live, pid] : stall.paused) {
      if (!live->child || live->child->pid() != pid || live->child->exited()) {
        gone += (gone.empty() ? "pid " : ", ") + std::to_string(pid);
        continue;
      }
      live->child->Signal(SIGCONT);
      live->stalled = false;
      // silence counts in the time it could run, and not before it has caught up
      live->last_health_ns = std::min(live->last_health_ns, stall.started_ns) + (now - stall.started_ns);
      live->silence_counts_from_ns = now + grace_ns;
    }
    record.paused_s = paused_s;
    if (!due) record.note = "cut short: " + reason;
    if (!gone.empty()) {
      record.note += (record.note.empty() ? "" : "; ") + gone + " ended during the stall (handled as any death)";
    }
    Event(stall.target, "stall_end",
          "planned at " + Fixed(stall.planned.stall.at_s(), 3) + " s for " +
              Fixed(stall.planned.stall.duration_s(), 3) + " s; paused at " + Fixed(*record.started_s, 3) + " s for " +
              Fixed(paused_s, 3) + " s" + (record.note.empty() ? "" : "; " + record.note));
  }
}

void Supervisor::PrintStatus(bool final_line) {
  std::ostringstream line;
  line << Fixed(Now(), 1) << " s";
  for (const auto& live : live_) {
    const ServiceRecord& record = record_->services[live->record_index];
    line << " | " << Spec(live->service.placed.service.kind).name;
    if (live->stalled) line << " STALLED";
    if (!record.last_health) {
      line << " (no health)";
      continue;
    }
    const v1::Health& h = *record.last_health;
    line << " " << ShortState(h.state());
    for (const v1::LoopStats& l : h.loops()) {
      line << " " << Fixed(h.uptime_s() > 0 ? static_cast<double>(l.ticks()) / h.uptime_s() : 0.0, 0) << " Hz p99 "
           << Fixed(l.period_p99_us(), 0) << " us ovr " << l.overruns();
    }
    for (const v1::LatencyStats& l : h.latencies()) {
      if (l.name() == "motion_to_force" && l.samples() > 0) line << " m2f p99 " << Fixed(l.p99_us(), 0) << " us";
      if (l.name() == "haptic_round_trip" && l.samples() > 0)
        line << " link rtt p50 " << Fixed(l.p50_us() * 1e-3, 1) << " ms";
    }
    for (const v1::Counter& c : h.counters()) {
      if ((c.name() == "frames_played" || c.name() == "force_models" || c.name() == "touch_traces") && c.value() > 0) {
        line << " " << c.name() << " " << c.value();
      }
    }
    if (record.restarts > 0) line << " restarts " << record.restarts;
    if (h.state() == v1::Health::STATE_DEGRADED && !h.last_error().empty())
      line << " (" << Printable(h.last_error()) << ")";
  }
  if (config_.status_in_place && !final_line) {
    out_ << "\r\x1b[K" << line.str() << std::flush;
  } else {
    out_ << line.str() << std::endl;
  }
}

void Supervisor::Stop() {
  Event("", "stopping", "zero force first, then each service, the device bridge last");
  HoldZeroForce(true, "stopping");
  const std::int64_t settle_until = base::SteadyNowNs() + static_cast<std::int64_t>(config_.zero_force_settle_s * 1e9);
  while (base::SteadyNowNs() < settle_until) {
    messenger_->WaitReadable(std::chrono::milliseconds(5));
    DrainHealth();
  }
  std::vector<Live*> order;
  for (auto& live : live_) order.push_back(live.get());
  std::stable_sort(order.begin(), order.end(), [](const Live* a, const Live* b) {
    return Spec(a->service.placed.service.kind).stop_rank < Spec(b->service.placed.service.kind).stop_rank;
  });
  for (Live* live : order) {
    if (!live->child) continue;
    const std::string name(Spec(live->service.placed.service.kind).name);
    ServiceRecord& record = record_->services[live->record_index];
    if (live->child->Poll()) {
      if (record.exit.empty()) record.exit = live->child->exit_text();
      continue;
    }
    SendControl(v1::Control::COMMAND_SHUTDOWN, live->service.placed.haptex.Peer(), name, "run ends");
    const auto wait_exit = [&](double seconds) {
      const std::int64_t until = base::SteadyNowNs() + static_cast<std::int64_t>(seconds * 1e9);
      while (base::SteadyNowNs() < until) {
        if (live->child->Poll()) return true;
        messenger_->WaitReadable(std::chrono::milliseconds(5));
        DrainHealth();
      }
      return live->child->Poll();
    };
    std::string how = "after SHUTDOWN";
    if (!wait_exit(config_.stop_timeout_s)) {
      live->child->Signal(SIGTERM);
      how = "after SIGTERM";
      if (!wait_exit(1.0)) {
        live->child->Signal(SIGKILL);
        how = "after SIGKILL";
        wait_exit(5.0);
      }
    }
    record.exit = live->child->exit_text();
    Event(name, "stopped", record.exit + " " + how);
  }
  StopRelays();
}

int Supervisor::Run(RunRecord* record) {
  record_ = record;
  start_ns_ = base::SteadyNowNs();
  runtime::InstallShutdownHandlers();
  for (const SupervisedService& s : config_.services) {
    auto live = std::make_unique<Live>();
    live->service = s;
    live->record_index = record_->services.size();
    ServiceRecord r;
    r.placed = s.placed;
    r.argv = s.argv;
    r.log_path = s.log_path;
    record_->services.push_back(std::move(r));
    live_.push_back(std::move(live));
  }
  for (const SupervisedRelay& s : config_.relays) {
    auto relay = std::make_unique<LiveRelay>();
    relay->relay = s;
    relay->name = "relay " + s.placed.Name();
    const auto same = std::find_if(record_->relays.begin(), record_->relays.end(),
                                   [&](const RelayRecord& r) { return r.placed.Name() == s.placed.Name(); });
    if (same == record_->relays.end()) {
      record_->relays.push_back({});
      record_->relays.back().placed = s.placed;
    }
    relay->record_index = same == record_->relays.end() ? record_->relays.size() - 1
                                                        : static_cast<std::size_t>(same - record_->relays.begin());
    RelayRecord& r = record_->relays[relay->record_index];
    r.argv = s.argv;
    r.log_path = s.log_path;
    r.local = true;
    relays_.push_back(std::move(relay));
  }

  for (const SupervisedStall& s : config_.stalls) {
    LiveStall stall;
    stall.planned = s;
    stall.target = scene::StallTarget(s.stall);
    stall.record_index = record_->stalls.size();
    StallRecord r;
    r.planned = s.stall;
    r.source = s.source;
    record_->stalls.push_back(std::move(r));
    stalls_.push_back(std::move(stall));
  }

  // the relays first: a service's first datagram to its peer already goes through one
  for (auto& relay : relays_) {
    if (!StartRelay(*relay)) {
      failed_ = !runtime::ShutdownRequested();
      break;
    }
  }
  // start in order, each healthy before the next; the bridge holds zero force meanwhile
  for (auto& live : live_) {
    if (failed_ || runtime::ShutdownRequested()) break;
    if (!Start(*live) || !WaitReady(*live)) {
      failed_ = !runtime::ShutdownRequested();
      break;
    }
    if (live->service.placed.service.kind == P::SERVICE_DEVICE_BRIDGE && live_.size() > 1) {
      HoldZeroForce(true, "holding zero force while the other services start");
    }
  }
  const bool all_started = !failed_ && !runtime::ShutdownRequested();
  if (all_started) {
    HoldZeroForce(false, "every service is healthy");
    Event("", "running", config_.duration_s > 0 ? "for " + Fixed(config_.duration_s, 1) + " s" : "until Ctrl-C");
  }
  run_start_ns_ = base::SteadyNowNs();

  // supervise
  while (all_started && !failed_) {
    if (runtime::ShutdownRequested()) break;
    if (config_.duration_s > 0 &&
        base::SteadyNowNs() - run_start_ns_ >= static_cast<std::int64_t>(config_.duration_s * 1e9))
      break;
    // 2 ms: a dead service is found within that, so the zero-force hold of its restart reaches
    // the device well inside 20 ms even when nothing else wakes the loop
    messenger_->WaitReadable(std::chrono::milliseconds(2));
    DrainHealth();
    CheckRelays();
    EndStalls();
    StartDueStalls();
    for (auto& live : live_) {
      std::string how;
      const std::int64_t now = base::SteadyNowNs();
      if (live->child->Poll()) {
        how = live->child->exit_text();
      } else if (!live->stalled && now >= live->silence_counts_from_ns &&
                 now - live->last_health_ns > static_cast<std::int64_t>(config_.silent_after_s * 1e9)) {
        how = "silent for " + Fixed(config_.silent_after_s, 1) + " s";
        live->child->Signal(SIGKILL);
        while (!live->child->Poll()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
      }
      if (!how.empty() && !Restart(*live, how)) {
        failed_ = !runtime::ShutdownRequested();
        break;
      }
    }
    if (base::SteadyNowNs() >= next_status_ns_) {
      PrintStatus(false);
      next_status_ns_ = base::SteadyNowNs() + static_cast<std::int64_t>(config_.status_period_s * 1e9);
    }
  }
  // before anything else: a stopped process would not hear its SHUTDOWN, nor SIGTERM
  EndStalls("the run stops");
  for (LiveStall& stall : stalls_) {
    if (!stall.started) record_->stalls[stall.record_index].note = "the run ended before its time";
  }
  if (config_.status_in_place) out_ << "\n";
  const int signal_number = runtime::ShutdownSignalNumber();
  record_->end_reason = failed_ ? "failed" : signal_number != 0 ? "interrupted" : "duration";
  if (signal_number != 0) Event("", "signal", "signal " + std::to_string(signal_number));
  Stop();
  PrintStatus(true);
  record_->duration_s = Now();
  for (std::size_t i = 0; i < net::kDropReasonCount; ++i) {
    const auto reason = static_cast<net::DropReason>(i);
    const std::uint64_t count = messenger_->received().Get(reason);
    if (count > 0) record_->launcher_received[std::string(net::DropReasonName(reason))] = count;
  }
  record_->exit_code = failed_ || relay_died_ ? 1 : 0;
  return record_->exit_code;
}

}  // namespace haptex::launch
