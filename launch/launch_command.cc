#include "launch/launch_command.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <memory>
#include <set>
#include <sstream>
#include <stdexcept>

#include "launch/command_line.h"
#include "launch/impair_option.h"
#include "launch/impaired_links.h"
#include "launch/port_plan.h"
#include "launch/recording.h"
#include "launch/run_folder.h"
#include "launch/run_mcap.h"
#include "launch/run_report.h"
#include "launch/run_summary.h"
#include "launch/service_set.h"
#include "launch/stall_option.h"
#include "launch/supervisor.h"
#include "libs/runtime/rt_setup.h"
#include "libs/scene/scene_defaults.h"
#include "libs/scene/scene_loader.h"
#include "libs/scene/session_key_source.h"

extern char** environ;

namespace haptex::launch {
namespace {

namespace fs = std::filesystem;

struct LaunchOptions {
  std::string scene;
  double duration_s = -1;  // < 0: the scene's
  std::string out;
  std::string host;
  std::vector<std::string> skip;
  int base_port = -1;  // < 0: free ports on one host, kDefaultMultiHostBasePort on several
  std::string build_dir;
  std::string log_level = "info";
  double ready_timeout_s = 30;
  double silent_after_s = 3;
  int max_restarts = 3;
  bool no_plots = false;
  // SCHED_FIFO for the launcher and, ranked by rate, every service; 0: normal scheduling. On by
  // default: on a busy host normal scheduling let the bridge's stall guard cut the force 16-83 times
  // in 15 s, and where the kernel refuses it the run goes on and says so.
  int rt_priority = runtime::kDefaultFifoPriority;
  bool dry_run = false;
  std::vector<std::string> impair;  // SERVICE-SERVICE[:KEY=VALUE,...], launch/impair_option.h
  std::vector<std::string> stall;   // TARGET@AT:DURATION, launch/stall_option.h
  int viewer_port = -1;             // < 0: the scene's; 0: any free port
  bool viewer = false;              // the viewer also where the scene has none
};

// The build folder: this executable is BUILD/cli/haptex.
std::string DefaultBuildDir() {
  std::error_code error;
  const fs::path self = fs::read_symlink("/proc/self/exe", error);
  if (error) return "build";
  return self.parent_path().parent_path().string();
}

// Binds a socket of `type` (SOCK_DGRAM, SOCK_STREAM) to `address`:`port` (0: any), reads the port
// it got and releases it; 0 when the bind is refused. Throws when no socket can be made.
std::uint16_t BindAndRelease(int type, in_addr_t address_be, std::uint16_t port) {
  const int fd = socket(AF_INET, type | SOCK_CLOEXEC, 0);
  if (fd < 0) throw std::runtime_error(std::string("no socket for a free port: ") + std::strerror(errno));
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = address_be;
  address.sin_port = htons(port);
  socklen_t length = sizeof(address);
  const bool ok = bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof(address)) == 0 &&
                  getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length) == 0;
  close(fd);
  return ok ? ntohs(address.sin_port) : 0;
}

// The viewer's TCP port: `wanted` when it is free on `bind_address` (0: any), else one the system
// has free now, so a second run or a test beside the first still gets its page.
std::uint16_t ViewerTcpPort(const std::string& bind_address, std::uint16_t wanted, bool* fell_back) {
  in_addr address{};
  if (inet_pton(AF_INET, bind_address.c_str(), &address) != 1) address.s_addr = htonl(INADDR_ANY);
  *fell_back = false;
  if (wanted != 0) {
    if (const std::uint16_t port = BindAndRelease(SOCK_STREAM, address.s_addr, wanted)) return port;
    *fell_back = true;
  }
  if (const std::uint16_t port = BindAndRelease(SOCK_STREAM, address.s_addr, 0)) return port;
  throw std::runtime_error(std::string("cannot find a free TCP port for the viewer: ") + std::strerror(errno));
}

// A port the system has free now (single-host runs): bind port 0, read it, release it.
std::uint16_t FreeUdpPort() {
  if (const std::uint16_t port = BindAndRelease(SOCK_DGRAM, htonl(INADDR_LOOPBACK), 0)) return port;
  throw std::runtime_error(std::string("cannot find a free UDP port: ") + std::strerror(errno));
}

std::string TimeStamp() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  localtime_r(&now, &tm);
  char text[32];
  std::strftime(text, sizeof(text), "%Y%m%d-%H%M%S", &tm);
  return text;
}

// --out as given, else a new folder under runs/ named by the scene's slug (created here, so that
// a launch in the same second gets its own; a dry run only shows the name).
std::string RunDirectory(const LaunchOptions& o, const std::string& scene_name) {
  if (!o.out.empty()) return fs::absolute(o.out).string();
  const std::string parent = fs::absolute("runs").string();
  const std::string stem = RunFolderStem(scene_name, TimeStamp(), o.host);
  return o.dry_run ? parent + "/" + RunFolderSlug(stem) : CreateUniqueRunFolder(parent, stem);
}

std::vector<std::string> ChildEnvironment(const net::SessionKey& key) {
  std::vector<std::string> env;
  for (char** e = environ; *e != nullptr; ++e) {
    if (std::strncmp(*e, "HAPTEX_SESSION_KEY=", 19) != 0) env.emplace_back(*e);
  }
  env.push_back("HAPTEX_SESSION_KEY=" + key.ToHex());
  return env;
}

// The haptex executable that runs this launcher: it runs the relays too.
std::string SelfPath(const std::string& build_dir) {
  std::error_code error;
  const fs::path self = fs::read_symlink("/proc/self/exe", error);
  return error ? build_dir + "/cli/haptex" : self.string();
}

// One record per impaired link (what was asked), and the relays this host starts.
std::vector<RelayRecord> PlanRelays(const std::vector<ImpairedLink>& links, const PortPlan& plan,
                                    const std::string& here, const CommandOptions& command_options,
                                    SupervisorConfig* config, std::string* plan_text) {
  std::vector<RelayRecord> records;
  for (std::size_t i = 0; i < links.size(); ++i) {
    RelayRecord r;
    r.placed = plan.relays.at(i);
    r.asked = links[i].link;
    r.source = links[i].source;
    r.directions = scene::ResolveLink(r.asked);
    r.local = r.placed.listen.host == here;
    r.argv = RelayCommandLine(r.placed, r.directions, plan, command_options, SelfPath(command_options.build_dir));
    r.report_path = RelayReportPath(command_options.run_dir, r.placed);
    *plan_text += "relay " + r.placed.Name() + " (" + r.placed.listen.host + "): " + JoinCommandLine(r.argv) + "\n";
    if (r.local) {
      r.log_path = command_options.run_dir + "/logs/relay_" + r.placed.Name() + ".log";
      config->relays.push_back({r.placed, r.argv, r.log_path});
      r.note = "the relay wrote no report";
    } else {
      r.note = "the relay runs on host " + r.placed.listen.host + ": its report is in that host's run folder";
    }
    records.push_back(std::move(r));
  }
  return records;
}

void PrintImpairedLinks(const std::vector<RelayRecord>& relays) {
  for (const RelayRecord& r : relays) {
    const std::string text = ImpairmentText(r.asked);
    std::cout << "  impair " << r.placed.Name() << " (" << r.source << "): " << (text.empty() ? "no impairment" : text)
              << "; through a relay on " << r.placed.listen.host << " (" << r.placed.listen.Peer() << ", "
              << r.placed.upstream.Peer() << ")\n";
  }
}

// After the run: what each relay of this host reports it did.
void ReadRelayReports(RunRecord* record) {
  for (RelayRecord& r : record->relays) {
    if (!r.local) continue;
    try {
      r.achieved = ReadRelayReport(r.report_path);
    } catch (const std::exception& e) {
      r.note = e.what();
      record->errors.push_back("relay " + r.placed.Name() + ": " + e.what());
    }
  }
}

// Which of the run's stalls this launcher carries out (into config), and a record of each it does
// not, with why; each printed (--dry-run too). A --stall of a service --skip'ped here is refused.
std::vector<StallRecord> PlanStalls(const std::vector<PlannedStall>& stalls, const v1::Scene& scene,
                                    const std::string& here, const std::set<std::string>& skip,
                                    const std::vector<PlacedService>& started_here, double run_duration_s,
                                    SupervisorConfig* config) {
  std::vector<StallRecord> elsewhere;
  for (const PlannedStall& p : stalls) {
    const v1::Stall& stall = p.stall;
    std::string pauses, not_here;
    if (stall.all()) {
      for (const PlacedService& s : started_here) {
        if (s.service.kind == v1::ServicePlacement::SERVICE_VIEWER) continue;
        pauses += (pauses.empty() ? "" : ", ") + std::string(Spec(s.service.kind).name);
      }
      pauses = "every service started here but the viewer (" + pauses + ")";
    } else {
      pauses = Spec(stall.service()).name;
      if (skip.count(pauses)) {
        not_here = pauses + " is --skip'ped: started by hand, not by this launcher";
        if (p.source == "--stall") {
          throw std::invalid_argument("--stall '" + p.text + "': " + not_here + "; pause a service it starts");
        }
      } else if (const std::string host = HostOf(scene, stall.service()); host != here) {
        not_here = pauses + " runs on host " + host + ": that host's launcher pauses it";
      }
    }
    std::cout << "  stall " << p.text << " (" << p.source << "): ";
    if (!not_here.empty()) {
      std::cout << "not here, " << not_here << "\n";
      StallRecord record;
      record.planned = stall;
      record.source = p.source;
      record.here = false;
      record.note = not_here;
      elsewhere.push_back(std::move(record));
      continue;
    }
    std::cout << "SIGSTOP to " << pauses << " " << stall.at_s() << " s after the run starts, SIGCONT "
              << stall.duration_s() << " s later";
    if (run_duration_s > 0 && stall.at_s() >= run_duration_s) {
      std::cout << "; after the run's end (" << run_duration_s << " s): it will not happen";
    }
    std::cout << "\n";
    config->stalls.push_back({stall, p.source});
  }
  return elsewhere;
}

void PrintRelayResults(const std::vector<RelayRecord>& relays) {
  const auto direction = [](const char* name, const RelayDirectionResult& d) {
    std::ostringstream line;
    line.precision(3);
    line << std::fixed << name << " received " << d.received << ", forwarded " << d.forwarded << ", dropped "
         << d.dropped_total << ", delay ms p50 " << d.delay_p50_ms << " p99 " << d.delay_p99_ms;
    return line.str();
  };
  for (const RelayRecord& r : relays) {
    if (!r.achieved) continue;
    std::cout << "network " << r.placed.Name() << ": " << direction("forward", r.achieved->forward) << "; "
              << direction("back", r.achieved->back) << "\n";
  }
}

int Launch(const LaunchOptions& o) {
  // the scene, validated (errors at file:line:column; main prints them and exits 2)
  const scene::FabricDatabase fabrics(scene::FabricDatabase::DefaultDirectory());
  const scene::LoadedScene loaded = scene::LoadScene(o.scene, fabrics);
  v1::Scene scene = loaded.scene;
  if (o.viewer) scene.mutable_viewer()->set_enabled(true);
  const std::string scene_path = fs::absolute(o.scene).string();

  // what it needs, and why
  const std::vector<PlannedService> services = DeriveServices(scene);
  std::set<std::string> skip(o.skip.begin(), o.skip.end());
  for (const std::string& name : skip) {
    const bool planned =
        std::any_of(services.begin(), services.end(), [&](const auto& s) { return Spec(s.kind).name == name; });
    if (!planned) throw std::invalid_argument("--skip " + name + ": the scene does not need a service of that name");
  }
  if (IsMultiHost(scene) && o.host.empty()) {
    throw std::invalid_argument("scene " + scene.name() +
                                " places services on several hosts: run `haptex launch SCENE --host NAME` on each");
  }
  const auto hosts = HostAddresses(scene);
  if (!o.host.empty() && !hosts.count(o.host)) {
    std::string known;
    for (const auto& [name, address] : hosts) known += (known.empty() ? "" : ", ") + name;
    throw std::invalid_argument("--host " + o.host + ": the scene has no such host (hosts: " + known + ")");
  }
  const std::vector<ImpairedLink> impaired = ImpairedLinks(scene, o.impair);
  const std::vector<PlannedStall> stalls = RunStalls(scene, o.stall);
  const std::string here = o.host.empty() ? "local" : o.host;
  const auto runs_here = [&](const PlannedService& s) {
    return HostOf(scene, s.kind) == here && !skip.count(std::string(Spec(s.kind).name));
  };

  std::cout << "scene " << scene.name() << " (" << scene_path << ")" << (o.host.empty() ? "" : ", host " + o.host)
            << "\n";
  for (const auto& s : services) {
    const std::string name(Spec(s.kind).name);
    const std::string where = HostOf(scene, s.kind);
    std::cout << "  "
              << (skip.count(name) ? "skip   "
                  : runs_here(s)   ? "start  "
                                   : "remote ")
              << name << (runs_here(s) || skip.count(name) ? "" : " (on " + where + ")") << ": " << s.reason << "\n";
  }
  for (const auto& s : OmittedServices(scene)) {
    std::cout << "  not    " << Spec(s.kind).name << ": " << s.reason << "\n";
  }

  // every executable started here must exist
  const std::string build_dir = o.build_dir.empty() ? DefaultBuildDir() : o.build_dir;
  std::string missing;
  for (const auto& s : services) {
    if (!runs_here(s)) continue;
    const std::string path = ExecutablePath(build_dir, s.kind);
    if (access(path.c_str(), X_OK) != 0) {
      const auto& spec = Spec(s.kind);
      missing += "\n  " + fs::path(path).filename().string() + " is not built (" + std::string(spec.built_by) +
                 "; looked for " + path + "); the scene needs it: " + s.reason + ". Build it, or pass --skip " +
                 std::string(spec.name) + " and start it yourself.";
    }
  }
  if (!missing.empty() && !o.dry_run)
    throw std::invalid_argument("cannot launch scene " + scene.name() + ":" + missing);

  // ports and command lines
  const std::uint16_t base_port = static_cast<std::uint16_t>(o.base_port >= 0     ? o.base_port
                                                             : IsMultiHost(scene) ? kDefaultMultiHostBasePort
                                                                                  : 0);
  const PortPlan plan = AssignPorts(scene, services, base_port, FreeUdpPort, LinksOf(impaired));
  const bool starts_any = std::any_of(plan.services.begin(), plan.services.end(),
                                      [&](const PlacedService& s) { return runs_here(s.service); });
  if (!starts_any && !o.dry_run) throw std::invalid_argument("nothing to start on host " + here);
  const std::string run_dir = RunDirectory(o, scene.name());
  CommandOptions command_options{build_dir, scene_path, run_dir, o.log_level};
  std::string viewer_line;
  if (const auto* viewer = plan.Find(v1::ServicePlacement::SERVICE_VIEWER); viewer && runs_here(viewer->service)) {
    const std::string bind = scene::ViewerBindAddress(scene);
    bool fell_back = false;
    const std::uint32_t wanted =
        o.viewer_port >= 0 ? static_cast<std::uint32_t>(o.viewer_port) : scene::ViewerPort(scene);
    command_options.viewer_http_port = ViewerTcpPort(bind, static_cast<std::uint16_t>(wanted), &fell_back);
    viewer_line = "viewer: open http://" + (bind == "0.0.0.0" ? std::string("127.0.0.1") : bind) + ":" +
                  std::to_string(command_options.viewer_http_port) + "/ (Foxglove: ws://" +
                  (bind == "0.0.0.0" ? std::string("127.0.0.1") : bind) + ":" +
                  std::to_string(command_options.viewer_http_port) + ")" +
                  (fell_back && wanted != 0 ? "; port " + std::to_string(wanted) + " was taken" : "");
  }
  SupervisorConfig config;
  config.launcher = plan.launchers.at(here);
  config.identity = o.host.empty() ? "launcher" : "launcher@" + o.host;
  if (const auto* bridge = plan.Find(v1::ServicePlacement::SERVICE_DEVICE_BRIDGE)) {
    if (!skip.count("device_bridge")) config.bridge_address = bridge->haptex.Peer();
  }
  std::string plan_text;
  for (const PlacedService& s : plan.services) {
    const auto argv = CommandLine(s, plan, scene, command_options);
    plan_text += std::string(Spec(s.service.kind).name) + " (" + s.haptex.host + "): " + JoinCommandLine(argv) + "\n";
    if (!runs_here(s.service)) continue;
    config.services.push_back({s, argv, run_dir + "/logs/" + std::string(Spec(s.service.kind).name) + ".log"});
  }
  std::vector<RelayRecord> relays = PlanRelays(impaired, plan, here, command_options, &config, &plan_text);
  PrintImpairedLinks(relays);
  std::vector<PlacedService> started_here;
  for (const SupervisedService& s : config.services) started_here.push_back(s.placed);
  const double run_duration_s = o.duration_s >= 0 ? o.duration_s : scene.duration_s();
  std::vector<StallRecord> stalls_elsewhere =
      PlanStalls(stalls, scene, here, skip, started_here, run_duration_s, &config);
  if (o.dry_run) {
    if (!missing.empty()) std::cout << "would refuse:" << missing << "\n";
    std::cout << "launcher@" << here << " on " << config.launcher.Peer() << "\n" << plan_text;
    return 0;
  }
  fs::create_directories(run_dir + "/logs");
  fs::create_directories(run_dir + "/recordings");
  if (!relays.empty()) fs::create_directories(run_dir + "/network");
  // a run folder that cannot take its first file (a full disk) would lose the run's record: refuse now
  WriteRunFile(run_dir + "/commands.txt", plan_text);
  // the scene as run, so the folder replays (haptex view) even after the scene file changes
  std::error_code copy_error;
  fs::copy_file(scene_path, run_dir + "/scene.textproto", fs::copy_options::overwrite_existing, copy_error);
  const net::SessionKey key = scene::ResolveSessionKey(scene.session_key());
  config.child_env = ChildEnvironment(key);
  config.duration_s = run_duration_s;
  config.ready_timeout_s = o.ready_timeout_s;
  config.silent_after_s = o.silent_after_s;
  config.max_restarts = o.max_restarts;
  config.status_in_place = isatty(STDOUT_FILENO) != 0;
  std::cout << "run folder " << run_dir << "\n"
            << "launcher receiving Health on " << config.launcher.Peer() << "; Ctrl-C stops the run" << std::endl;
  if (!viewer_line.empty()) std::cout << viewer_line << std::endl;

  std::string scheduling = "normal scheduling (--rt-priority 0)";
  if (o.rt_priority > 0) {
    // Services run below the launcher by their rate (ServiceSpec::rt_rank), relays at the haptic link's.
    const runtime::RtSetupResult rt = runtime::TrySetFifoPriority(o.rt_priority);
    scheduling = rt.ok ? "real-time: " + rt.message +
                             " for the launcher; the services below it by rate (5 kHz loops at the same, "
                             "local_contact and relays 1 lower, tactile 2, global_sim 3)"
                       : "real-time refused (" + rt.message + "): normal scheduling";
    std::cout << scheduling << std::endl;
    if (rt.ok) config.rt_priority = o.rt_priority;
  }

  RunRecord record;
  record.scene_name = scene.name();
  record.scene_path = scene_path;
  record.run_dir = run_dir;
  record.host = o.host;
  record.rt_priority = config.rt_priority;
  record.scheduling = scheduling;
  record.not_needed = OmittedServices(scene);
  record.skipped.assign(skip.begin(), skip.end());
  record.relays = std::move(relays);
  const int code = [&] {
    Supervisor supervisor(config, key, std::cout);
    return supervisor.Run(&record);
  }();
  for (StallRecord& s : stalls_elsewhere) record.stalls.push_back(std::move(s));
  // services that run elsewhere are listed with their addresses
  for (const PlacedService& s : plan.services) {
    if (runs_here(s.service)) continue;
    ServiceRecord remote;
    remote.placed = s;
    remote.local = false;
    record.services.push_back(remote);
  }

  ReadRelayReports(&record);
  // a recording the disk did not take (the services count what their writers could not write)
  bool recordings_incomplete = false;
  for (const ServiceRecord& s : record.services) {
    if (!s.last_health) continue;
    for (const v1::Counter& c : s.last_health->counters()) {
      if (c.name() == "record_write_errors" && c.value() > 0) {
        record.errors.push_back(std::string(Spec(s.placed.service.kind).name) + ": " + std::to_string(c.value()) +
                                " recording writes failed (a full disk?): " + run_dir + "/recordings is incomplete");
        recordings_incomplete = true;
      }
      // not an error (the device was kept safe), but the run did not feel like its scene
      if (c.name() == "continuous_limited_ticks" && c.value() > 0) {
        std::cout << "note: " << Spec(s.placed.service.kind).name << ": the device's continuous force limit held "
                  << "the force down in " << c.value() << " ticks: the scene asks for more force, for longer, "
                  << "than the device gives (docs/grab-protocol.md, force limits)\n";
      }
    }
    // each resume after a cut whose force the bound held down, and each contact a cut ended
    std::vector<const v1::ForceResume*> resumes;
    for (const v1::ForceResume& r : s.last_health->resumes()) {
      // (a zero the launcher held, at a restart or the run's end, is its own doing: not noted)
      if (r.number() != 0 && (r.limited() || r.ended()) && r.cause() != v1::ForceResume::CAUSE_HELD_OFF) {
        resumes.push_back(&r);
      }
    }
    std::sort(resumes.begin(), resumes.end(), [](auto* a, auto* b) { return a->number() < b->number(); });
    for (const v1::ForceResume* r : resumes) {
      const std::string cause = v1::ForceResume::Cause_Name(r->cause());
      std::cout << "note: " << Spec(s.placed.service.kind).name << ": " << (r->finger_slot() == 0 ? "thumb" : "index")
                << " force cut at " << r->cut_at_s() << " s (" << cause.substr(cause.find('_') + 1) << ") "
                << (r->ended()
                        ? "for too long: the contact ended at zero force"
                        : "resumed within its bound: asked " + std::to_string(r->asked_n()) + " N, gave " +
                              std::to_string(r->peak_n()) + " N, held " + std::to_string(r->held_n()) + " N before")
                << "\n";
    }
  }

  // the run folder: recordings, what they say, plots, summary.json
  std::vector<Recording> recordings;
  std::vector<RecordingFiles> files;
  try {
    recordings = ReadRecordings(run_dir + "/recordings");
  } catch (const std::exception& e) {
    record.errors.push_back(e.what());
  }
  for (const auto& r : recordings) {
    files.push_back({fs::path(r.path).filename().string(), r.envelopes.size(), r.unparsable, r.truncated});
  }
  std::optional<RunMcapCounts> mcap;
  try {
    mcap = WriteRunMcap(recordings, run_dir + "/run.mcap");
  } catch (const std::exception& e) {
    record.errors.push_back(std::string("run.mcap: ") + e.what());
  }
  const auto analysis = AnalyseRecordings(recordings);
  const auto force_log = ReadForceLog(ForceLogPath(run_dir));
  std::vector<PlotResult> plots;
  if (!o.no_plots) {
    FigureReference reference;
    try {
      reference = FigureReferenceFromScene(loaded);
    } catch (const std::exception& e) {
      record.errors.push_back(std::string("figure references: ") + e.what());
    }
    plots = MakePlots(run_dir, scene, recordings, force_log, reference);
  }
  std::string summary_error;
  try {
    WriteRunFile(run_dir + "/summary.json", SummaryJson(record, files, analysis, force_log, plots, mcap));
  } catch (const std::exception& e) {
    summary_error = e.what();
    record.errors.push_back(summary_error);
  }

  PrintRelayResults(record.relays);
  for (const std::string& e : record.errors) std::cout << "error: " << e << "\n";
  if (mcap) {
    std::cout << "recording " << run_dir << "/run.mcap: " << mcap->messages << " messages on " << mcap->channels.size()
              << " channels\n";
  }
  for (const auto& p : plots) {
    std::cout << "plot " << p.name << ": " << (p.file.empty() ? "skipped, " + p.skipped : p.file) << "\n";
    if (!p.note.empty()) std::cout << "  " << p.note << "\n";
  }
  if (!summary_error.empty()) {
    std::cout << "run " << record.end_reason << " after " << record.duration_s
              << " s; no summary.json (the error above)" << std::endl;
    return 1;
  }
  std::cout << "run " << record.end_reason << " after " << record.duration_s << " s; summary " << run_dir
            << "/summary.json" << std::endl;
  return code != 0 ? code : (recordings_incomplete ? 1 : 0);
}

}  // namespace

void AddLaunchCommand(CLI::App& app, int* exit_code) {
  auto o = std::make_shared<LaunchOptions>();
  CLI::App* launch = app.add_subcommand("launch", "Run a scene: start what it needs, supervise, stop safely");
  launch->add_option("SCENE", o->scene, "scene file (.textproto)")->required();
  launch->add_option("--duration", o->duration_s, "seconds to run (default: the scene's; 0: until Ctrl-C)")
      ->check(CLI::Range(0.0, 1e7));
  launch->add_option("--out", o->out, "run folder, used as given (default: a new runs/SCENE-TIME, SCENE made safe)");
  launch->add_option("--host", o->host, "start only the services the scene places on this host");
  launch->add_option("--skip", o->skip, "a needed service not to start here (started by hand elsewhere); repeatable");
  launch
      ->add_option("--base-port", o->base_port,
                   "ports are this + a fixed offset per service (default: free ports on one host, " +
                       std::to_string(kDefaultMultiHostBasePort) + " on several)")
      ->check(CLI::Range(1, 65000));
  launch->add_option("--build-dir", o->build_dir, "where the service executables are (default: this haptex's build)");
  launch->add_option("--log-level", o->log_level, "the services' log level")->capture_default_str();
  launch->add_option("--ready-timeout", o->ready_timeout_s, "seconds a service may take to report healthy")
      ->check(CLI::Range(0.5, 600.0))
      ->capture_default_str();
  launch->add_option("--silent-after", o->silent_after_s, "seconds without Health before a service is restarted")
      ->check(CLI::Range(0.5, 600.0))
      ->capture_default_str();
  launch->add_option("--max-restarts", o->max_restarts, "restarts per service before the run stops")
      ->check(CLI::Range(0, 100))
      ->capture_default_str();
  launch->add_flag("--no-plots", o->no_plots, "do not draw the plots");
  launch
      ->add_option("--rt-priority", o->rt_priority,
                   "SCHED_FIFO priority 1..99 for the launcher and every service it starts, ranked by rate, "
                   "memory locked (0: normal scheduling; needs root or CAP_SYS_NICE, else the run goes on "
                   "with normal scheduling and says so)")
      ->check(CLI::Range(0, 99))
      ->capture_default_str();
  launch->add_flag("--dry-run", o->dry_run, "print the services, ports and command lines; start nothing");
  launch
      ->add_option("--impair", o->impair,
                   "put the link between two services through an impairment relay, e.g. "
                   "device_bridge-local_contact:rtt_ms=100,jitter_ms=5,loss=0.05 (keys: the scene's LinkImpairment "
                   "fields; replaces the scene's link of that pair); repeatable")
      ->allow_extra_args(false);  // one link per --impair: the scene after it stays the scene
  launch
      ->add_option("--stall", o->stall,
                   "pause a service's process (SIGSTOP), or every service's with all, at a time after the run "
                   "starts and let it go on (SIGCONT) after a while, as a host that pauses would: TARGET@AT:DURATION, "
                   "units s or ms, e.g. local_contact@4.5s:30ms or all@4.5s:30ms (adds to the scene's stalls); "
                   "repeatable")
      ->allow_extra_args(false);  // one stall per --stall: the scene after it stays the scene
  launch->add_flag("--viewer", o->viewer, "start the viewer even where the scene does not ask for it");
  launch
      ->add_option("--viewer-port", o->viewer_port,
                   "the viewer's page and WebSocket port (default: the scene's viewer.port, else 8765; 0: any free "
                   "port; a taken port falls back to a free one)")
      ->check(CLI::Range(0, 65535));
  launch->callback([o, exit_code] { *exit_code = Launch(*o); });
}

}  // namespace haptex::launch
