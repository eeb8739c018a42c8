#pragma once
// Command-line options shared by every haptex service; the launcher passes them.

#include <cstdint>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "libs/runtime/rt_options.h"

namespace haptex::services {

struct ServiceOptions {
  std::string scene_path;            // --scene: the scene file (optional for stand-ins)
  std::string bind = "127.0.0.1:0";  // --bind HOST:PORT
  std::vector<std::string> peers;    // --peer NAME=HOST:PORT (repeatable)
  std::string key_file;              // --key-file, else $HAPTEX_SESSION_KEY
  std::uint64_t session_id = 0;      // --session-id; 0: derived from the key
  std::string log_level = "info";    // --log-level
  std::string log_file;              // --log-file
  runtime::RtOptions rt;             // --rt-priority, --cpu, --lock-memory
  double health_hz = 5.0;            // --health-hz (Health to the "launcher" peer)
  double duration_s = 0.0;           // --duration: stop after this long (0: until told)
  std::string record_path;           // --record FILE: the messages this service sends (off the loop)
};

/// Adds the shared options to a service's CLI11 app.
void AddServiceOptions(CLI::App& app, ServiceOptions* options);

/// Splits "NAME=HOST:PORT"; throws std::invalid_argument otherwise.
std::pair<std::string, std::string> ParsePeer(const std::string& text);

}  // namespace haptex::services
