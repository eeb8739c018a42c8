#include "launch/run_summary.h"

#include <algorithm>
#include <cctype>
#include <limits>
#include <vector>

#include "launch/impair_option.h"
#include "launch/json_writer.h"
#include "libs/scene/scene_stalls.h"

namespace haptex::launch {
namespace {

std::string ResumeCauseName(v1::ForceResume::Cause cause) {
  std::string name = v1::ForceResume::Cause_Name(cause);
  if (name.starts_with("CAUSE_")) name = name.substr(6);
  std::transform(name.begin(), name.end(), name.begin(), [](unsigned char ch) { return std::tolower(ch); });
  return name;
}

void WriteForce(JsonWriter& j, std::string_view key, const FingerForceStats& s) {
  j.BeginObject(key)
      .Field("samples", s.samples)
      .Field("peak_n", s.peak_n)
      .Field("mean_n", s.mean_n)
      .Field("final_n", s.final_n)
      .EndObject();
}

void WriteHealth(JsonWriter& j, const v1::Health& h) {
  j.Field("state", v1::Health::State_Name(h.state())).Field("uptime_s", h.uptime_s());
  j.BeginArray("loops");
  for (const v1::LoopStats& l : h.loops()) {
    j.BeginObject()
        .Field("name", l.name())
        .Field("target_rate_hz", l.target_rate_hz())
        .Field("rate_hz", h.uptime_s() > 0 ? static_cast<double>(l.ticks()) / h.uptime_s() : 0.0)
        .Field("ticks", l.ticks())
        .Field("overruns", l.overruns())
        .Field("period_p50_us", l.period_p50_us())
        .Field("period_p99_us", l.period_p99_us())
        .Field("period_max_us", l.period_max_us())
        .Field("compute_p50_us", l.compute_p50_us())
        .Field("compute_p99_us", l.compute_p99_us())
        .Field("compute_max_us", l.compute_max_us())
        .EndObject();
  }
  j.EndArray();
  j.BeginObject("latencies");
  for (const v1::LatencyStats& l : h.latencies()) {
    j.BeginObject(l.name())
        .Field("samples", l.samples())
        .Field("p50_us", l.p50_us())
        .Field("p99_us", l.p99_us())
        .Field("max_us", l.max_us())
        .EndObject();
  }
  j.EndObject();
  j.BeginObject("counters");
  for (const v1::Counter& c : h.counters()) j.Field(c.name(), c.value());
  j.EndObject();
  if (h.resumes_size() > 0) {  // the bridge's newest resumes after a cut, oldest first
    j.BeginArray("resumes");
    std::vector<const v1::ForceResume*> resumes;
    for (const v1::ForceResume& r : h.resumes()) {
      if (r.number() != 0) resumes.push_back(&r);
    }
    std::sort(resumes.begin(), resumes.end(), [](auto* a, auto* b) { return a->number() < b->number(); });
    for (const v1::ForceResume* r : resumes) {
      j.BeginObject()
          .Field("number", r->number())
          .Field("cause", ResumeCauseName(r->cause()))
          .Field("finger", r->finger_slot() == 0 ? "thumb" : "index")
          .Field("cut_at_s", r->cut_at_s())
          .Field("held_n", r->held_n())
          .Field("asked_n", r->asked_n())
          .Field("peak_n", r->peak_n())
          .Field("peak_over_held", r->held_n() > 0 ? r->peak_n() / r->held_n() : 0.0)
          .Field("limited", r->limited())
          .Field("ended", r->ended())
          .EndObject();
    }
    j.EndArray();
  }
  j.Field("last_error", h.last_error());
}

// counters that are watchdog or device events, by name
bool IsWatchdogCounter(const std::string& name) {
  if (name.starts_with("datagrams_dropped")) return false;  // transport drops, listed under drops
  return name == "device_lost_events" || name == "host_timeouts" || name == "non_finite_forces" ||
         name == "tick_gap_disarms" || name == "tick_gaps_held" || name == "world_pauses" ||
         name.find("watchdog") != std::string::npos || name.find("stale") != std::string::npos ||
         name.ends_with("_limited_ticks") || name.starts_with("held_cuts_") || name == "host_timeout_cuts" ||
         name == "resumes_limited" || name == "contacts_ended";
}

void WriteAskedDirection(JsonWriter& j, std::string_view key, const netsim::ImpairmentConfig& c, std::uint64_t seed) {
  j.BeginObject(key)
      .Field("delay_ms", c.delay_ms)
      .Field("jitter_ms", c.jitter_ms)
      .Field("jitter_distribution", netsim::JitterDistributionName(c.jitter_distribution))
      .Field("loss", c.loss)
      .BeginObject("burst_loss")
      .Field("p", c.burst.p_good_to_bad)
      .Field("r", c.burst.p_bad_to_good)
      .Field("loss_bad", c.burst.loss_bad)
      .Field("loss_good", c.burst.loss_good)
      .EndObject()
      .Field("reorder", c.reorder)
      .Field("reorder_delay_ms", c.reorder_delay_ms)
      .Field("duplicate", c.duplicate)
      .Field("rate_kbps", c.rate_kbps)
      .Field("outage_after_s", c.outage_after_s)
      .Field("outage_s", c.outage_s)
      .Field("seed", seed)
      .EndObject();
}

void WriteAchievedDirection(JsonWriter& j, std::string_view key, const RelayDirectionResult& r) {
  j.BeginObject(key)
      .Field("received", r.received)
      .Field("forwarded", r.forwarded)
      .Field("duplicated", r.duplicated)
      .Field("reordered", r.reordered)
      .Field("held_back", r.held_back)
      .Field("dropped_total", r.dropped_total)
      .BeginObject("dropped");
  for (const auto& [cause, count] : r.dropped) j.Field(cause, count);
  j.EndObject()
      .Field("in_flight", r.in_flight)
      .BeginObject("delay_ms")
      .Field("p50", r.delay_p50_ms)
      .Field("p99", r.delay_p99_ms)
      .Field("max", r.delay_max_ms)
      .Field("mean", r.delay_mean_ms)
      .EndObject()
      .EndObject();
}

// Per impaired link: what was asked (per direction, as the relay was told) and what its relay's
// report says it did.
void WriteNetwork(JsonWriter& j, const std::vector<RelayRecord>& relays) {
  j.BeginObject("network").BeginArray("links");
  for (const RelayRecord& r : relays) {
    const std::string a(Spec(r.placed.a).name), b(Spec(r.placed.b).name);
    j.BeginObject()
        .Field("link", r.placed.Name())
        .Field("a", a)
        .Field("b", b)
        .Field("source", r.source)
        .Field("carries", r.placed.device_link ? "the GRAB protocol" : "haptex datagrams")
        .BeginObject("directions")
        .Field("forward", a + " -> " + b)
        .Field("back", b + " -> " + a)
        .EndObject()
        .Field("relay_host", r.placed.listen.host)
        .Field("started_here", r.local)
        .Field("listen", r.placed.listen.Peer())
        .Field("upstream", r.placed.upstream.Peer());
    if (r.local) {
      j.Field("log", r.log_path).Field("report", r.report_path).Field("pid", r.pid).Field("exit", r.exit);
    }
    j.BeginObject("asked").Field("text", ImpairmentText(r.asked)).Field("rtt_ms", r.asked.rtt_ms());
    WriteAskedDirection(j, "forward", r.directions.forward, r.directions.forward_seed);
    WriteAskedDirection(j, "back", r.directions.back, r.directions.back_seed);
    j.EndObject();
    j.BeginObject("achieved");
    if (r.achieved) {
      j.Field("duration_s", r.achieved->duration_s);
      WriteAchievedDirection(j, "forward", r.achieved->forward);
      WriteAchievedDirection(j, "back", r.achieved->back);
    } else {
      j.Field("note", r.note);
    }
    j.EndObject().EndObject();
  }
  j.EndArray().EndObject();
}

// Per stall: what was planned (from the run's start) and what the launcher did, on its clock;
// null where it did not happen.
void WriteStalls(JsonWriter& j, const std::vector<StallRecord>& stalls) {
  constexpr double kNone = std::numeric_limits<double>::quiet_NaN();  // written as null
  j.BeginArray("stalls");
  for (const StallRecord& s : stalls) {
    j.BeginObject()
        .Field("target", scene::StallTarget(s.planned))
        .Field("source", s.source)
        .Field("started_here", s.here)
        .Field("at_s", s.planned.at_s())
        .Field("started_s", s.started_s.value_or(kNone))
        .Field("duration_s", s.planned.duration_s())
        .Field("paused_s", s.paused_s.value_or(kNone));
    j.BeginArray("pids");
    for (int pid : s.pids) j.Field({}, pid);
    j.EndArray();
    if (!s.note.empty()) j.Field("note", s.note);
    j.EndObject();
  }
  j.EndArray();
}

}  // namespace

std::string SummaryJson(const RunRecord& run, const std::vector<RecordingFiles>& recordings,
                        const RecordingAnalysis& analysis, const std::optional<ForceLog>& force_log,
                        const std::vector<PlotResult>& plots, const std::optional<RunMcapCounts>& mcap) {
  JsonWriter j;
  j.BeginObject();
  j.Field("scene", run.scene_name).Field("scene_path", run.scene_path).Field("run_dir", run.run_dir);
  j.Field("host", run.host.empty() ? std::string("all") : run.host);
  j.Field("duration_s", run.duration_s).Field("end_reason", run.end_reason).Field("exit_code", run.exit_code);
  j.BeginObject("scheduling").Field("rt_priority", run.rt_priority).Field("note", run.scheduling).EndObject();

  // services: what ran, why, and its last Health
  j.BeginArray("services");
  for (const ServiceRecord& s : run.services) {
    const ServiceSpec& spec = Spec(s.placed.service.kind);
    j.BeginObject().Field("name", spec.name).Field("reason", s.placed.service.reason);
    j.Field("host", s.placed.haptex.host).Field("address", s.placed.haptex.Peer());
    if (s.placed.controller) j.Field("controller_address", s.placed.controller->Peer());
    j.Field("started_here", s.local).Field("health_received", s.last_health.has_value());
    if (s.local) {
      j.Field("log", s.log_path).Field("restarts", s.restarts).Field("exit", s.exit);
      j.BeginArray("pids");
      for (int pid : s.pids) j.BeginObject().Field("pid", pid).EndObject();
      j.EndArray();
    }
    if (s.last_health) WriteHealth(j, *s.last_health);
    j.EndObject();
  }
  j.EndArray();
  j.BeginArray("not_started");
  for (const PlannedService& s : run.not_needed) {
    j.BeginObject().Field("name", Spec(s.kind).name).Field("why", s.reason).EndObject();
  }
  for (const std::string& name : run.skipped) {
    j.BeginObject().Field("name", name).Field("why", "--skip (started elsewhere)").EndObject();
  }
  j.EndArray();
  WriteNetwork(j, run.relays);
  WriteStalls(j, run.stalls);

  // motion-to-force latency (the bridge's clock)
  j.BeginObject("motion_to_force");
  for (const ServiceRecord& s : run.services) {
    if (!s.last_health) continue;
    for (const v1::LatencyStats& l : s.last_health->latencies()) {
      if (l.name() != "motion_to_force") continue;
      j.Field("service", Spec(s.placed.service.kind).name)
          .Field("samples", l.samples())
          .Field("p50_us", l.p50_us())
          .Field("p99_us", l.p99_us())
          .Field("max_us", l.max_us());
    }
  }
  j.EndObject();

  // dropped datagrams: each service's counters, and the launcher's own per reason
  j.BeginObject("drops");
  for (const ServiceRecord& s : run.services) {
    if (!s.last_health) continue;
    j.BeginObject(Spec(s.placed.service.kind).name);
    for (const v1::Counter& c : s.last_health->counters()) {
      if (c.name().find("dropped") != std::string::npos || c.name().find("rejected") != std::string::npos) {
        j.Field(c.name(), c.value());
      }
    }
    j.EndObject();
  }
  j.BeginObject("launcher_received");
  for (const auto& [reason, count] : run.launcher_received) j.Field(reason, count);
  j.EndObject();
  j.EndObject();

  // contact states and forces
  j.BeginObject("contact_states");
  if (analysis.force_models == 0) {
    j.Field("note", "no ForceModel recorded (local_contact did not run or did not record)");
  } else {
    for (int state = 1; state <= 9; ++state) j.Field(RomanState(state), analysis.contact_states[state]);
    j.Field("unspecified", analysis.contact_states[0]);
  }
  j.EndObject();
  j.BeginObject("forces");
  j.BeginObject("force_model");
  if (analysis.model_forces.empty()) j.Field("note", "no ForceModel recorded");
  for (const auto& [finger, stats] : analysis.model_forces) WriteForce(j, finger, stats);
  j.EndObject();
  j.BeginObject("mock_controller_commanded");
  if (!force_log) {
    j.Field("note", "no mock controller force log");
  } else {
    WriteForce(j, "thumb", force_log->stats[0]);
    WriteForce(j, "index", force_log->stats[1]);
    const double minutes = force_log->t_s.empty() ? 0.0 : force_log->t_s.back() / 60.0;
    j.Field("force_dropouts", force_log->dropouts)
        .Field("force_dropouts_per_minute", minutes > 0.0 ? static_cast<double>(force_log->dropouts) / minutes : 0.0);
  }
  j.EndObject();
  j.EndObject();

  // watchdogs, restarts and the launcher's other events
  j.BeginArray("watchdog");
  for (const ServiceRecord& s : run.services) {
    if (!s.last_health) continue;
    for (const v1::Counter& c : s.last_health->counters()) {
      if (IsWatchdogCounter(c.name())) {
        j.BeginObject()
            .Field("service", Spec(s.placed.service.kind).name)
            .Field("counter", c.name())
            .Field("value", c.value())
            .EndObject();
      }
    }
  }
  j.EndArray();
  j.BeginArray("restarts");
  for (const RunEvent& e : run.events) {
    if (e.kind == "restarted")
      j.BeginObject().Field("t_s", e.t_s).Field("service", e.service).Field("detail", e.detail).EndObject();
  }
  j.EndArray();
  j.BeginArray("events");
  for (const RunEvent& e : run.events) {
    j.BeginObject()
        .Field("t_s", e.t_s)
        .Field("service", e.service)
        .Field("kind", e.kind)
        .Field("detail", e.detail)
        .EndObject();
  }
  j.EndArray();
  j.BeginArray("errors");
  for (const std::string& e : run.errors) j.BeginObject().Field("error", e).EndObject();
  for (const ServiceRecord& s : run.services) {
    if (s.last_health && !s.last_health->last_error().empty()) {
      j.BeginObject()
          .Field("error", std::string(Spec(s.placed.service.kind).name) + ": " + s.last_health->last_error())
          .EndObject();
    }
  }
  j.EndArray();

  j.BeginArray("recordings");
  for (const RecordingFiles& r : recordings) {
    j.BeginObject()
        .Field("file", r.name)
        .Field("envelopes", static_cast<std::uint64_t>(r.envelopes))
        .Field("unparsable", static_cast<std::uint64_t>(r.unparsable))
        .Field("truncated", r.truncated)
        .EndObject();
  }
  j.EndArray();
  // run.mcap, assembled from the recordings: messages per topic as written
  j.BeginObject("recording");
  if (mcap) {
    j.Field("mcap", mcap->file).Field("messages", mcap->messages).Field("without_body", mcap->without_body);
    j.BeginObject("channels");
    for (const auto& [topic, count] : mcap->channels) j.Field(topic, count);
    j.EndObject();
  } else {
    j.Field("mcap", "").Field("note", "run.mcap was not written (see errors)");
  }
  j.EndObject();
  j.BeginObject("plots");
  for (const PlotResult& p : plots) {
    j.BeginObject(p.name);
    if (p.file.empty()) {
      j.Field("skipped", p.skipped);
    } else {
      j.Field("file", p.file);
    }
    if (!p.measured.empty()) {
      j.BeginObject("measured");
      for (const auto& [key, value] : p.measured) j.Field(key, value);
      j.EndObject();
    }
    if (!p.note.empty()) j.Field("note", p.note);
    j.EndObject();
  }
  j.EndObject();
  j.EndObject();
  return j.str() + "\n";
}

}  // namespace haptex::launch
