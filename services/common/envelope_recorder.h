#pragma once
// Records the messages a service sends, off its hot loop: the loop encodes each body into an
// Envelope in a fixed slot of a bounded single-producer single-consumer ring; a writer thread
// drains the ring to the file as length-delimited Envelopes (varint length, then the bytes, as
// protobuf's writeDelimitedTo). A full ring or a message larger than a slot is dropped and
// counted; Record never allocates, blocks or logs.

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>
#include <thread>

#include "libs/net/envelope_body.h"

namespace haptex::services {

class EnvelopeRecorder final {
 public:
  static constexpr std::size_t kSlotBytes = 4096;
  static constexpr std::size_t kSlots = 512;  // power of two

  /// Opens (truncates) `path` and starts the writer thread. Throws std::invalid_argument when the
  /// file cannot be written.
  EnvelopeRecorder(const std::string& path, std::string_view sender, std::uint64_t sender_epoch,
                   std::uint64_t session_id);
  /// Writes everything still in the ring, then closes the file.
  ~EnvelopeRecorder();
  EnvelopeRecorder(const EnvelopeRecorder&) = delete;
  EnvelopeRecorder& operator=(const EnvelopeRecorder&) = delete;

  /// Loop side (one thread only): records `body` as sent at `send_time_ns` (steady clock).
  /// False when it was dropped (ring full, or larger than a slot).
  template <class Body>
  bool Record(const Body& body, std::int64_t send_time_ns) {
    const std::size_t body_bytes = body.ByteSizeLong();
    std::uint8_t* slot = ClaimSlot(body_bytes);
    if (slot == nullptr) return false;
    std::uint8_t* at = WriteHeader(slot, net::EnvelopeBody<Body>::kFieldNumber, body_bytes, send_time_ns);
    at = body.SerializeWithCachedSizesToArray(at);
    Commit(static_cast<std::size_t>(at - slot));
    return true;
  }

  std::uint64_t recorded() const { return recorded_.load(std::memory_order_relaxed); }
  std::uint64_t dropped() const { return dropped_.load(std::memory_order_relaxed); }
  /// Write errors seen by the writer thread (disk full, ...).
  std::uint64_t write_errors() const { return write_errors_.load(std::memory_order_relaxed); }

 private:
  struct Slot {
    std::uint32_t bytes = 0;
    std::array<std::uint8_t, kSlotBytes> data{};
  };

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
  std::array<Slot, kSlots> slots_;
  alignas(64) std::atomic<std::size_t> head_{0};
  alignas(64) std::atomic<std::size_t> tail_{0};
  std::atomic<std::uint64_t> recorded_{0};
  std::atomic<std::uint64_t> dropped_{0};
  std::atomic<std::uint64_t> write_errors_{0};
  std::atomic<bool> stop_{false};
  std::thread writer_;
};

}  // namespace haptex::services
