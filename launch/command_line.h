#pragma once
// The command line of each service of a run: executable, the shared options (scene, bind, peers,
// Health rate, recording) and the service's own flags; and of the relay of each impaired link,
// whose two sockets stand in for each end's peer address. Pure.

#include <string>
#include <vector>

#include "haptex/v1/scene.pb.h"
#include "launch/port_plan.h"
#include "libs/scene/scene_network.h"

namespace haptex::launch {

struct CommandOptions {
  std::string build_dir;   // where the executables are (the table's paths are relative to it)
  std::string scene_path;  // absolute path of the scene file
  std::string run_dir;     // the run folder (recordings, force log, pin log)
  std::string log_level = "info";
  int viewer_http_port = -1;  // the viewer's page and WebSocket; < 0: the scene's
};

/// Path of a service's executable.
std::string ExecutablePath(const std::string& build_dir, ServiceKind kind);
/// Path of a service's recording in the run folder.
std::string RecordingPath(const std::string& run_dir, ServiceKind kind);
/// The mock controller's force log (what the fingers felt) in the run folder.
std::string ForceLogPath(const std::string& run_dir);

/// The JSON report a relay writes into the run folder when it stops.
std::string RelayReportPath(const std::string& run_dir, const PlacedRelay& relay);

/// argv for `service` (argv[0] = the executable). The session key is not on the command line:
/// children get it in HAPTEX_SESSION_KEY. A peer behind a relay is given as the relay's socket.
std::vector<std::string> CommandLine(const PlacedService& service, const PortPlan& plan, const v1::Scene& scene,
                                     const CommandOptions& options);

/// argv for the relay of one impaired link: `haptex relay` (run by `haptex_path`) listening where a
/// sends, forwarding to b's real address from the socket b sends to, back to a's real address, each
/// direction's impairment (flags left out where they would say the relay's default) and its JSON
/// report.
std::vector<std::string> RelayCommandLine(const PlacedRelay& relay, const scene::LinkDirections& directions,
                                          const PortPlan& plan, const CommandOptions& options,
                                          const std::string& haptex_path);

/// argv joined with spaces, arguments with spaces quoted (for logs and the run folder).
std::string JoinCommandLine(const std::vector<std::string>& argv);

}  // namespace haptex::launch
