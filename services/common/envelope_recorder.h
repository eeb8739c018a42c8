#pragma once
// Records the messages a service sends, off its hot loop: the loop encodes each body into an
// Envelope in a bounded single-producer single-consumer byte ring (records of any size, each
// where it fits, so a 100 KB LocalPatch is kept like a 100-byte Health); a writer thread drains
// the ring to the file as length-delimited Envelopes (varint length, then the bytes, as
// protobuf's writeDelimitedTo). Only a full ring (the disk slower than the sender for seconds) or
// a message over a quarter of the ring drops, and it is counted; Record never allocates, blocks
// or logs.

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <string_view>
#include <thread>

#include <google/protobuf/message_lite.h>

#include "libs/net/envelope_body.h"

namespace haptex::services {

class EnvelopeRecorder final {
 public:
  static constexpr std::size_t kRingBytes = std::size_t{16} << 20;  // 16 MiB, a multiple of 8
  static constexpr std::size_t kMaxRecordBytes = kRingBytes / 4;

  /// Opens (truncates) `path` and starts the writer thread. Throws std::invalid_argument when the
  /// file cannot be written.
  EnvelopeRecorder(const std::string& path, std::string_view sender, std::uint64_t sender_epoch,
                   std::uint64_t session_id);
  /// Writes everything still in the ring, then closes the file.
  ~EnvelopeRecorder();
  EnvelopeRecorder(const EnvelopeRecorder&) = delete;
  EnvelopeRecorder& operator=(const EnvelopeRecorder&) = delete;

  /// Loop side (one thread only): records `body` as sent at `send_time_ns` (steady clock).
  /// False when it was dropped (ring full, or larger than kMaxRecordBytes).
  template <class Body>
  bool Record(const Body& body, std::int64_t send_time_ns) {
    return RecordBody(body, net::EnvelopeBody<Body>::kFieldNumber, send_time_ns);
  }
  /// Same, for a body chosen at run time (`body_field_number`: its field in the Envelope oneof).
  bool RecordBody(const google::protobuf::MessageLite& body, int body_field_number, std::int64_t send_time_ns) {
    const std::size_t body_bytes = body.ByteSizeLong();
    std::uint8_t* slot = ClaimSlot(body_bytes);
    if (slot == nullptr) return false;
    std::uint8_t* at = WriteHeader(slot, body_field_number, body_bytes, send_time_ns);
    at = body.SerializeWithCachedSizesToArray(at);
    Commit(static_cast<std::size_t>(at - slot));
    return true;
  }

  std::uint64_t recorded() const { return recorded_.load(std::memory_order_relaxed); }
  std::uint64_t dropped() const { return dropped_.load(std::memory_order_relaxed); }
  /// Write errors seen by the writer thread (disk full, ...).
  std::uint64_t write_errors() const { return write_errors_.load(std::memory_order_relaxed); }

 private:
  std::uint8_t* ClaimSlot(std::size_t body_bytes);
  std::uint8_t* WriteHeader(std::uint8_t* at, int field_number, std::size_t body_bytes, std::int64_t send_time_ns);
  void Commit(std::size_t bytes);
  void WriteWaiting();

  std::FILE* file_ = nullptr;
  std::array<std::uint8_t, 64> sender_{};
  std::size_t sender_bytes_ = 0;
  std::uint64_t sender_epoch_;
  std::uint64_t session_id_;
  std::uint64_t sequence_ = 0;
  // Records in the ring: a 4-byte length, the bytes, padding to 8; a length of kWrap means the
  // rest of the ring up to its end is unused and the next record starts at 0.
  std::unique_ptr<std::uint8_t[]> ring_;
  std::size_t claim_skip_ = 0, claim_start_ = 0;  // the claimed record (loop side only)
  alignas(64) std::atomic<std::size_t> head_{0};  // bytes ever written / read (positions mod kRingBytes)
  alignas(64) std::atomic<std::size_t> tail_{0};
  std::atomic<std::uint64_t> recorded_{0};
  std::atomic<std::uint64_t> dropped_{0};
  std::atomic<std::uint64_t> write_errors_{0};
  std::atomic<bool> stop_{false};
  std::thread writer_;
};

}  // namespace haptex::services
