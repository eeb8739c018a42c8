#pragma once
// Reading a service's recording: length-delimited Envelopes (a varint length, then the bytes),
// as services/common's EnvelopeRecorder writes them.

#include <cstddef>
#include <string>
#include <vector>

#include "haptex/v1/envelope.pb.h"

namespace haptex::launch {

struct Recording {
  std::string path;
  std::vector<v1::Envelope> envelopes;
  std::size_t unparsable = 0;  // records that were not an Envelope
  bool truncated = false;      // the file ends inside a record (a service killed mid-write)
};

/// Throws std::runtime_error when the file cannot be read or is not a regular file (a device or a
/// pipe named like a recording would be read forever or block).
Recording ReadRecording(const std::string& path);

/// Every regular *.pb file in `folder` (symlinks followed), sorted by name; an empty list when the
/// folder does not exist.
std::vector<Recording> ReadRecordings(const std::string& folder);

/// The earliest send time in the recordings [ns, steady clock of the recording machine]; 0 if none.
std::int64_t EarliestSendTimeNs(const std::vector<Recording>& recordings);

}  // namespace haptex::launch
