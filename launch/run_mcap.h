#pragma once
// run.mcap: a run's recordings as one MCAP file (libs/mcap), which Foxglove, Rerun and any MCAP
// reader open. One channel per sending service and body type, topic "/<service>/<body>" (the
// Envelope's oneof field name, e.g. "/global_sim/cloth_frame"), message and schema encoding
// "protobuf"; the schema is the body's full type name (e.g. "haptex.v1.ClothFrame") with a
// FileDescriptorSet of its file and every file it imports, so a reader needs nothing else to decode.
// A message is the body's bytes (not the Envelope); log and publish time are the Envelope's send
// time as recorded [ns on the sender's steady clock, not offset]. The .pb recordings stay the
// source: each service writes its own, and run.mcap is assembled from them after the run.

#include <cstddef>
#include <cstdint>
#include <map>
#include <ostream>
#include <string>
#include <vector>

#include "launch/recording.h"

namespace haptex::launch {

/// What run.mcap holds, for summary.json.
struct RunMcapCounts {
  std::string file;  // its name in the run folder
  std::uint64_t messages = 0;
  std::map<std::string, std::uint64_t> channels;  // messages per topic
  std::uint64_t without_body = 0;                 // envelopes with no body: not written
};

/// Writes run.mcap from the recordings to `out`, messages in send-time order; returns what it holds
/// (`file` empty). Throws mcap::McapError when the stream fails.
RunMcapCounts WriteRunMcap(const std::vector<Recording>& recordings, std::ostream& out);

/// Writes it at `path`. Throws std::runtime_error when it cannot be written.
RunMcapCounts WriteRunMcap(const std::vector<Recording>& recordings, const std::string& path);

/// Its bytes, in memory (tests, small runs); `counts` (may be null) says what it holds.
std::string MakeRunMcap(const std::vector<Recording>& recordings, RunMcapCounts* counts);

/// The recordings again from a run.mcap, one per sending service (sorted by name), its Envelopes
/// holding sender, sequence, send time and body. Throws std::runtime_error (mcap::McapError) for a
/// missing, truncated or damaged file, and for an MCAP file that is not a haptex run's.
std::vector<Recording> RecordingsFromMcap(const std::string& path);

}  // namespace haptex::launch
