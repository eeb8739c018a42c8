#pragma once
// Runs one host's part of a launch: starts the services in order, waits for each to report
// healthy, holds the device at zero force while anything (re)starts, restarts a service that dies
// or goes silent (bounded), prints a live status line, and stops in a safe order: Control
// ZERO_FORCE to the bridge first, then SHUTDOWN to each service (the device bridge last of the
// haptex services), then SIGTERM and SIGKILL for a service that does not exit. The relays of
// impaired links start before the services and stop (SIGTERM: each writes its report) after them;
// they send no Health, and one that dies is an error of the run, not restarted. Stalls on purpose
// stop a service's process (SIGSTOP), or every service's, at a moment of the run and let it go on
// (SIGCONT) after a while; a stalled service is not taken for silent, and every stalled process
// goes on before the stop begins.

#include <iosfwd>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "launch/run_summary.h"
#include "libs/net/messenger.h"

namespace haptex::launch {

struct SupervisedService {
  PlacedService placed;
  std::vector<std::string> argv;
  std::string log_path;
};

struct SupervisedRelay {
  PlacedRelay placed;
  std::vector<std::string> argv;
  std::string log_path;
};

struct SupervisedStall {
  v1::Stall stall;     // a service started here, or all: every service started here but the viewer
  std::string source;  // "scene" or "--stall"
};

struct SupervisorConfig {
  std::vector<SupervisedService> services;  // started here, in start order
  std::vector<SupervisedRelay> relays;      // started here before the services, stopped after them
  HostPort launcher;                        // where this launcher receives Health
  std::string identity = "launcher";        // sender name of this launcher
  std::string bridge_address;               // where ZERO_FORCE / ENABLE_FORCE go; "" without a bridge
  std::vector<std::string> child_env;       // the services' environment (with the session key)
  double duration_s = 0;                    // 0: until Ctrl-C (SIGINT/SIGTERM)
  double ready_timeout_s = 30;              // per service start
  double silent_after_s = 3;                // no Health for this long: restarted
  int max_restarts = 3;                     // per service
  std::vector<SupervisedStall> stalls;      // carried out here, at_s after the run starts
  // After a stall, before silence counts again for what it paused: a process that goes on first
  // catches up on its loop before its next Health.
  double stall_grace_s = 1;
  double stop_timeout_s = 3;          // after SHUTDOWN, before SIGTERM
  double zero_force_settle_s = 0.06;  // between ZERO_FORCE and the first SHUTDOWN
  double status_period_s = 1;
  bool status_in_place = false;  // rewrite one line (a terminal) instead of printing lines
  int rt_priority = 0;           // > 0: the launcher's SCHED_FIFO priority; services run below it by rt_rank
};

class Supervisor final {
 public:
  /// Binds the launcher's socket. Throws std::runtime_error when it cannot.
  Supervisor(SupervisorConfig config, const net::SessionKey& key, std::ostream& out);
  ~Supervisor();
  Supervisor(const Supervisor&) = delete;
  Supervisor& operator=(const Supervisor&) = delete;

  /// Runs until the duration ends, a signal arrives, or a service fails for good. Fills
  /// record->services (in start order), events, errors, end_reason and duration. Returns the exit
  /// code: 0 for a duration end or a signal, 1 when a service could not be kept running.
  int Run(RunRecord* record);

 private:
  struct Live;
  struct LiveRelay;
  struct LiveStall;
  double Now() const;
  void Event(const std::string& service, const std::string& kind, const std::string& detail);
  void DrainHealth();
  void SendControl(v1::Control::Command command, const std::string& target_address, const std::string& target,
                   const std::string& reason);
  void HoldZeroForce(bool hold, const std::string& reason);
  bool Start(Live& live);
  bool WaitReady(Live& live);
  bool Restart(Live& live, const std::string& how);
  void Stop();
  bool StartRelay(LiveRelay& relay);
  void CheckRelays();
  void StopRelays();
  void StartDueStalls();
  /// Lets each stall whose time is up go on (all of them with `reason`: the run stops).
  void EndStalls(const std::string& reason = "");
  void PrintStatus(bool final_line);

  SupervisorConfig config_;
  std::ostream& out_;
  std::unique_ptr<net::Messenger> messenger_;
  std::vector<std::unique_ptr<Live>> live_;
  std::vector<std::unique_ptr<LiveRelay>> relays_;
  std::vector<LiveStall> stalls_;
  RunRecord* record_ = nullptr;
  std::int64_t start_ns_ = 0;
  std::int64_t run_start_ns_ = 0;  // every service healthy, force enabled: what stalls' at_s count from
  std::int64_t next_status_ns_ = 0;
  bool failed_ = false;
  bool relay_died_ = false;
};

}  // namespace haptex::launch
