#pragma once
// Protobuf writes its own log lines (e.g. when a peer sends invalid UTF-8 in a string field) from
// whatever thread parses. Services capture them into a counter instead, so a hot loop that
// decodes a datagram never writes to stderr.

#include <cstdint>

namespace haptex::runtime {

/// Replaces protobuf's log handler with one that only counts (process-wide, idempotent).
void CaptureProtobufLogs();
/// Protobuf log messages swallowed since CaptureProtobufLogs().
std::uint64_t CapturedProtobufLogCount();

}  // namespace haptex::runtime
