// summary.json: the fields a run folder promises, from a hand-made run record.
#include "launch/run_summary.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace haptex::launch {
namespace {

using P = v1::ServicePlacement;
using ::testing::HasSubstr;

TEST(LaunchRunSummaryTest, ServicesLatencyDropsEventsAndNotes) {
  RunRecord run;
  run.scene_name = "demo";
  run.end_reason = "interrupted";
  ServiceRecord bridge;
  bridge.placed = {{P::SERVICE_DEVICE_BRIDGE, "fingers on a device"}, {"local", "127.0.0.1", 40003}, std::nullopt};
  bridge.restarts = 1;
  bridge.exit = "exit 0";
  bridge.pids = {11, 12};
  v1::Health h;
  h.set_state(v1::Health::STATE_READY);
  h.set_uptime_s(2);
  auto* loop = h.add_loops();
  loop->set_name("device_bridge");
  loop->set_ticks(10000);
  loop->set_period_p99_us(250);
  auto* m2f = h.add_latencies();
  m2f->set_name("motion_to_force");
  m2f->set_p99_us(120);
  auto* dropped = h.add_counters();
  dropped->set_name("datagrams_dropped");
  dropped->set_value(3);
  auto* lost = h.add_counters();
  lost->set_name("device_lost_events");
  lost->set_value(1);
  // a per-reason counter of docs/grab-protocol.md section 6 (BridgeLoop's Health)
  auto* bad_checksum = h.add_counters();
  bad_checksum->set_name("status_frames_rejected_bad_checksum");
  bad_checksum->set_value(4);
  bridge.last_health = h;
  run.services.push_back(bridge);
  run.not_needed.push_back({P::SERVICE_TACTILE, "tactile display off"});
  run.events.push_back({1.5, "device_bridge", "restarted", "after signal 9"});
  run.errors.push_back("something broke");
  run.launcher_received["bad_mac"] = 2;
  run.rt_priority = 40;
  run.scheduling = "real-time: SCHED_FIFO 40";

  RecordingAnalysis analysis;
  ForceLog log;
  log.stats[0] = {10, 2.0, 1.0, 0.0};
  log.t_s = {0.0, 30.0};
  log.dropouts = 3;
  const std::string json = SummaryJson(run, {{"device_bridge.pb", 12, 0, false}}, analysis, log,
                                       {{"forces", "/r/plots/forces.png", ""}, {"friction_ratio", "", "no data"}});
  EXPECT_THAT(json, HasSubstr(R"("end_reason":"interrupted")"));
  EXPECT_THAT(json, HasSubstr(R"("name":"device_bridge","reason":"fingers on a device")"));
  EXPECT_THAT(json, HasSubstr(R"("rate_hz":5000)"));
  EXPECT_THAT(json, HasSubstr(R"("period_p99_us":250)"));
  EXPECT_THAT(json, HasSubstr(R"("motion_to_force":{"service":"device_bridge")"));
  EXPECT_THAT(json, HasSubstr(R"("device_bridge":{"datagrams_dropped":3,"status_frames_rejected_bad_checksum":4})"));
  EXPECT_THAT(json, HasSubstr(R"("device_lost_events":1,"status_frames_rejected_bad_checksum":4})"));
  EXPECT_THAT(json, HasSubstr(R"("launcher_received":{"bad_mac":2})"));
  EXPECT_THAT(json, HasSubstr(R"("counter":"device_lost_events","value":1)"));
  EXPECT_THAT(json, HasSubstr(R"("restarts":[{"t_s":1.5,"service":"device_bridge")"));
  EXPECT_THAT(json, HasSubstr(R"("contact_states":{"note":"no ForceModel recorded)"));
  EXPECT_THAT(json, HasSubstr(R"("thumb":{"samples":10,"peak_n":2,"mean_n":1,"final_n":0})"));
  EXPECT_THAT(json, HasSubstr(R"("force_dropouts":3,"force_dropouts_per_minute":6)"));
  EXPECT_THAT(json, HasSubstr(R"("scheduling":{"rt_priority":40,"note":"real-time: SCHED_FIFO 40"})"));
  EXPECT_THAT(json, HasSubstr(R"("not_started":[{"name":"tactile","why":"tactile display off"})"));
  EXPECT_THAT(json, HasSubstr(R"("friction_ratio":{"skipped":"no data"})"));
  EXPECT_THAT(json, HasSubstr(R"("error":"something broke")"));
  EXPECT_THAT(json, HasSubstr(R"("file":"device_bridge.pb","envelopes":12)"));
}

TEST(LaunchRunSummaryTest, ContactStateHistogram) {
  RunRecord run;
  RecordingAnalysis analysis;
  analysis.force_models = 3;
  analysis.contact_states[5] = 2;
  analysis.contact_states[9] = 1;
  const std::string json = SummaryJson(run, {}, analysis, std::nullopt, {});
  EXPECT_THAT(json, HasSubstr(R"("contact_states":{"I":0,"II":0,"III":0,"IV":0,"V":2,)"));
  EXPECT_THAT(json, HasSubstr(R"("IX":1)"));
  EXPECT_THAT(json, HasSubstr(R"("mock_controller_commanded":{"note":"no mock controller force log"})"));
}

TEST(LaunchRunSummaryTest, RecordingSectionCountsRunMcap) {
  RunMcapCounts mcap;
  mcap.file = "run.mcap";
  mcap.messages = 7;
  mcap.channels = {{"/device_bridge/finger_states", 5}, {"/global_sim/cloth_frame", 2}};
  const std::string json = SummaryJson(RunRecord{}, {}, RecordingAnalysis{}, std::nullopt, {}, mcap);
  EXPECT_THAT(json, HasSubstr(R"("recording":{"mcap":"run.mcap","messages":7,"without_body":0,)"
                              R"("channels":{"/device_bridge/finger_states":5,"/global_sim/cloth_frame":2}})"));
  const std::string without = SummaryJson(RunRecord{}, {}, RecordingAnalysis{}, std::nullopt, {});
  EXPECT_THAT(without, HasSubstr(R"("recording":{"mcap":"","note":)"));
}

TEST(LaunchRunSummaryTest, NetworkSectionHasAskedAndAchievedPerLink) {
  RunRecord run;
  const std::string json_without = SummaryJson(run, {}, RecordingAnalysis{}, std::nullopt, {});
  EXPECT_THAT(json_without, HasSubstr(R"("network":{"links":[]})"));

  RelayRecord relay;
  relay.placed = {P::SERVICE_DEVICE_BRIDGE,
                  P::SERVICE_LOCAL_CONTACT,
                  false,
                  {"local", "127.0.0.1", 40040},
                  {"local", "127.0.0.1", 40041}};
  relay.asked.set_a(P::SERVICE_DEVICE_BRIDGE);
  relay.asked.set_b(P::SERVICE_LOCAL_CONTACT);
  relay.asked.set_rtt_ms(20);
  relay.asked.set_loss(0.02);
  relay.asked.set_seed(1);
  relay.directions = scene::ResolveLink(relay.asked);
  relay.source = "--impair";
  relay.pid = 42;
  relay.exit = "exit 0";
  relay.report_path = "/run/network/device_bridge-local_contact.json";
  RelayResult achieved;
  achieved.duration_s = 5;
  achieved.forward.received = 1000;
  achieved.forward.forwarded = 980;
  achieved.forward.dropped_total = 20;
  achieved.forward.dropped = {{"loss", 20}, {"queue_overflow", 0}};
  achieved.forward.delay_p50_ms = 10.02;
  relay.achieved = achieved;
  run.relays.push_back(relay);
  RelayRecord remote = relay;
  remote.local = false;
  remote.achieved.reset();
  remote.note = "the relay runs on host lab";
  run.relays.push_back(remote);

  const std::string json = SummaryJson(run, {}, RecordingAnalysis{}, std::nullopt, {});
  EXPECT_THAT(json, HasSubstr(R"("network":{"links":[{"link":"device_bridge-local_contact","a":"device_bridge",)"
                              R"("b":"local_contact","source":"--impair","carries":"haptex datagrams",)"
                              R"("directions":{"forward":"device_bridge -> local_contact","back":"local_contact -> )"
                              R"(device_bridge"},"relay_host":"local","started_here":true,)"
                              R"("listen":"127.0.0.1:40040","upstream":"127.0.0.1:40041")"));
  EXPECT_THAT(json, HasSubstr(R"("report":"/run/network/device_bridge-local_contact.json","pid":42,"exit":"exit 0")"));
  EXPECT_THAT(json,
              HasSubstr(R"("asked":{"text":"rtt_ms=20,loss=0.02,seed=1","rtt_ms":20,)"
                        R"("forward":{"delay_ms":10,"jitter_ms":0,"jitter_distribution":"uniform","loss":0.02,)"));
  EXPECT_THAT(json, HasSubstr(R"("rate_kbps":0,"outage_after_s":0,"outage_s":0,"seed":2})"));  // back's seed
  EXPECT_THAT(json, HasSubstr(R"("achieved":{"duration_s":5,"forward":{"received":1000,"forwarded":980,)"
                              R"("duplicated":0,"reordered":0,"held_back":0,"dropped_total":20,)"
                              R"("dropped":{"loss":20,"queue_overflow":0},"in_flight":0,"delay_ms":{"p50":10.02,)"));
  EXPECT_THAT(json, HasSubstr(R"("started_here":false)"));
  EXPECT_THAT(json, HasSubstr(R"("achieved":{"note":"the relay runs on host lab"})"));
}

TEST(LaunchRunSummaryTest, StallsSectionHasPlannedAndActualPerStall) {
  EXPECT_THAT(SummaryJson(RunRecord{}, {}, RecordingAnalysis{}, std::nullopt, {}), HasSubstr(R"("stalls":[])"));
  RunRecord run;
  StallRecord paused;
  paused.planned.set_service(P::SERVICE_LOCAL_CONTACT);
  paused.planned.set_at_s(1.5);
  paused.planned.set_duration_s(0.1);
  paused.source = "--stall";
  paused.started_s = 1.502;
  paused.paused_s = 0.1013;
  paused.pids = {4242};
  run.stalls.push_back(paused);
  StallRecord later;  // never reached
  later.planned.set_all(true);
  later.planned.set_at_s(60);
  later.planned.set_duration_s(0.03);
  later.source = "scene";
  later.note = "the run ended before its time";
  run.stalls.push_back(later);
  StallRecord remote = paused;
  remote.here = false;
  remote.started_s.reset();
  remote.paused_s.reset();
  remote.pids.clear();
  remote.note = "local_contact runs on host compute: that host's launcher pauses it";
  run.stalls.push_back(remote);

  const std::string json = SummaryJson(run, {}, RecordingAnalysis{}, std::nullopt, {});
  EXPECT_THAT(json, HasSubstr(R"("stalls":[{"target":"local_contact","source":"--stall","started_here":true,)"
                              R"("at_s":1.5,"started_s":1.502,"duration_s":0.1,"paused_s":0.1013,"pids":[4242]},)"));
  EXPECT_THAT(json,
              HasSubstr(R"({"target":"all","source":"scene","started_here":true,"at_s":60,"started_s":null,)"
                        R"("duration_s":0.03,"paused_s":null,"pids":[],"note":"the run ended before its time"})"));
  EXPECT_THAT(json, HasSubstr(R"("started_here":false,"at_s":1.5,"started_s":null,"duration_s":0.1,"paused_s":null,)"
                              R"("pids":[],"note":"local_contact runs on host compute)"));
}

}  // namespace
}  // namespace haptex::launch
