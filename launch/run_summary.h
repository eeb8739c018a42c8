#pragma once
// What a run leaves in summary.json: per service loop statistics, latencies, counters (drops,
// watchdogs) from its last Health, the launcher's events (starts, deaths, restarts, zero force),
// errors, and what the recordings and the force log say. Pure: JSON text from the record.

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "haptex/v1/health.pb.h"
#include "launch/port_plan.h"
#include "launch/relay_report_reader.h"
#include "launch/run_mcap.h"
#include "launch/run_report.h"
#include "libs/scene/scene_network.h"

namespace haptex::launch {

struct RunEvent {
  double t_s = 0;       // since the launcher started
  std::string service;  // "" for the run itself
  std::string kind;     // started, ready, exited, silent, restarted, zero_force, enable_force, shutdown, ...
  std::string detail;
};

struct ServiceRecord {
  PlacedService placed;
  std::vector<std::string> argv;
  std::string log_path;
  std::vector<int> pids;  // one per start
  std::optional<v1::Health> last_health;
  int restarts = 0;
  double restart_s = 0;  // the last restart's time from death to ready
  std::string exit;      // how it ended ("exit 0", "signal 9", ...)
  bool local = true;     // started by this launcher
};

/// One impaired link: what was asked, its relay, and what the relay's report says it achieved.
struct RelayRecord {
  PlacedRelay placed;
  v1::LinkImpairment asked;
  scene::LinkDirections directions;  // what `asked` means for each direction
  std::string source;                // "scene" or "--impair"
  bool local = true;                 // the relay is started by this launcher
  std::vector<std::string> argv;
  std::string log_path;
  std::string report_path;
  int pid = 0;
  std::string exit;                     // how it ended ("exit 0", "signal 9", ...)
  std::optional<RelayResult> achieved;  // from its JSON report
  std::string note;                     // why there is no report
};

/// One stall of the run: what was planned and what the launcher did, on its clock in seconds from
/// the run's start (as at_s).
struct StallRecord {
  v1::Stall planned;
  std::string source;               // "scene" or "--stall"
  bool here = true;                 // carried out by this launcher
  std::optional<double> started_s;  // the SIGSTOPs sent
  std::optional<double> paused_s;   // from then until the first SIGCONT: each process paused at least this
  std::vector<int> pids;            // the processes it paused
  std::string note;                 // why it did not happen here, or not in full
};

struct RunRecord {
  std::string scene_name;
  std::string scene_path;
  std::string run_dir;
  std::string host;        // --host, "" for all
  double duration_s = 0;   // wall time from the first start to the end of the stop
  std::string end_reason;  // "duration", "interrupted", "failed"
  int exit_code = 0;
  int rt_priority = 0;     // the launcher's SCHED_FIFO priority (services ranked below it); 0: normal
  std::string scheduling;  // what was asked and what the kernel allowed, in words
  std::vector<ServiceRecord> services;
  std::vector<RelayRecord> relays;         // one per impaired link
  std::vector<StallRecord> stalls;         // the supervisor's, then those not carried out here
  std::vector<PlannedService> not_needed;  // with why
  std::vector<std::string> skipped;        // --skip: needed but started elsewhere
  std::vector<RunEvent> events;
  std::vector<std::string> errors;
  std::map<std::string, std::uint64_t> launcher_received;  // the launcher's own datagrams per drop reason
};

struct RecordingFiles {
  std::string name;
  std::size_t envelopes = 0;
  std::size_t unparsable = 0;
  bool truncated = false;
};

/// summary.json's text. `mcap`: what run.mcap holds (none when it could not be written).
std::string SummaryJson(const RunRecord& run, const std::vector<RecordingFiles>& recordings,
                        const RecordingAnalysis& analysis, const std::optional<ForceLog>& force_log,
                        const std::vector<PlotResult>& plots, const std::optional<RunMcapCounts>& mcap = std::nullopt);

}  // namespace haptex::launch
