#include "services/common/service_options.h"

#include <stdexcept>

namespace haptex::services {

void AddServiceOptions(CLI::App& app, ServiceOptions* o) {
  app.add_option("--scene", o->scene_path, "scene file (.textproto)");
  app.add_option("--bind", o->bind, "UDP address to receive on, HOST:PORT")->capture_default_str();
  app.add_option("--peer", o->peers, "a peer to send to, NAME=HOST:PORT (repeatable)");
  app.add_option("--key-file", o->key_file, "session key file (default: $HAPTEX_SESSION_KEY)");
  app.add_option("--session-id", o->session_id, "session id of this run (0: derived from the key)");
  app.add_option("--log-level", o->log_level, "trace, debug, info, warn, error, critical or off")
      ->capture_default_str();
  app.add_option("--log-file", o->log_file, "also log to this file");
  app.add_option("--rt-priority", o->rt.fifo_priority, "SCHED_FIFO priority 1..99 (0: normal)")
      ->check(CLI::Range(0, 99));
  app.add_option("--cpu", o->rt.cpus, "pin the loop to these CPUs");
  app.add_flag("--lock-memory", o->rt.lock_memory, "mlockall (no page faults in the loop)");
  app.add_option("--health-hz", o->health_hz, "Health messages per second to the launcher")
      ->check(CLI::Range(0.1, 1000.0))
      ->capture_default_str();
  app.add_option("--duration", o->duration_s, "stop after this many seconds (0: until told)")
      ->check(CLI::Range(0.0, 1e7));
  app.add_option("--record", o->record_path,
                 "record the messages this service sends to FILE (length-delimited Envelopes)");
}

std::pair<std::string, std::string> ParsePeer(const std::string& text) {
  const auto equals = text.find('=');
  if (equals == std::string::npos || equals == 0 || equals + 1 == text.size()) {
    throw std::invalid_argument("peer '" + text + "' must be NAME=HOST:PORT");
  }
  return {text.substr(0, equals), text.substr(equals + 1)};
}

}  // namespace haptex::services
