#include "services/common/envelope_recorder.h"

#include <chrono>
#include <cstring>
#include <stdexcept>

namespace haptex::services {
namespace {

// protobuf wire types
constexpr std::uint32_t kVarint = 0, kFixed64 = 1, kLengthDelimited = 2;

std::uint8_t* PutVarint(std::uint64_t value, std::uint8_t* at) {
  while (value >= 0x80) {
    *at++ = static_cast<std::uint8_t>(value | 0x80);
    value >>= 7;
  }
  *at++ = static_cast<std::uint8_t>(value);
  return at;
}

std::uint8_t* PutTag(int field, std::uint32_t wire_type, std::uint8_t* at) {
  return PutVarint((static_cast<std::uint64_t>(field) << 3) | wire_type, at);
}

std::uint8_t* PutFixed64(std::uint64_t value, std::uint8_t* at) {
  for (int i = 0; i < 8; ++i) *at++ = static_cast<std::uint8_t>(value >> (8 * i));
  return at;
}

constexpr std::uint32_t kWrap = 0xFFFFFFFFu;
constexpr std::size_t kLengthBytes = 4;

std::size_t Align8(std::size_t n) { return (n + 7) & ~std::size_t{7}; }

void PutLength(std::uint32_t n, std::uint8_t* at) { std::memcpy(at, &n, kLengthBytes); }
std::uint32_t GetLength(const std::uint8_t* at) {
  std::uint32_t n = 0;
  std::memcpy(&n, at, kLengthBytes);
  return n;
}

}  // namespace

EnvelopeRecorder::EnvelopeRecorder(const std::string& path, std::string_view sender, std::uint64_t sender_epoch,
                                   std::uint64_t session_id)
    : sender_epoch_(sender_epoch), session_id_(session_id), ring_(new std::uint8_t[kRingBytes]) {
  if (sender.size() > sender_.size()) throw std::invalid_argument("recorder: sender name too long");
  std::memcpy(sender_.data(), sender.data(), sender.size());
  sender_bytes_ = sender.size();
  // touch every page now, so the first pass through the ring does not fault in the sender's loop
  std::memset(ring_.get(), 0, kRingBytes);
  file_ = std::fopen(path.c_str(), "wb");
  if (file_ == nullptr) throw std::invalid_argument("--record: cannot write " + path);
  writer_ = std::thread([this] {
    while (!stop_.load(std::memory_order_acquire)) {
      WriteWaiting();
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    WriteWaiting();
  });
}

EnvelopeRecorder::~EnvelopeRecorder() {
  stop_.store(true, std::memory_order_release);
  writer_.join();
  if (std::fflush(file_) != 0) write_errors_.fetch_add(1, std::memory_order_relaxed);
  std::fclose(file_);
}

std::uint8_t* EnvelopeRecorder::ClaimSlot(std::size_t body_bytes) {
  // header: version, session, sender, epoch, sequence, send time, body tag + length (< 64 + sender)
  const std::size_t most = body_bytes + 64 + sender_bytes_;
  if (most > kMaxRecordBytes) {
    dropped_.fetch_add(1, std::memory_order_relaxed);
    return nullptr;
  }
  const std::size_t need = Align8(kLengthBytes + most);
  const std::size_t head = head_.load(std::memory_order_relaxed);
  const std::size_t at = head % kRingBytes;
  // a record is contiguous: when it does not fit before the ring's end, it starts at 0
  claim_skip_ = need > kRingBytes - at ? kRingBytes - at : 0;
  claim_start_ = claim_skip_ > 0 ? 0 : at;
  if (head - tail_.load(std::memory_order_acquire) + claim_skip_ + need > kRingBytes) {
    dropped_.fetch_add(1, std::memory_order_relaxed);
    return nullptr;
  }
  if (claim_skip_ > 0) PutLength(kWrap, ring_.get() + at);  // at is 8-aligned: 4 bytes fit
  return ring_.get() + claim_start_ + kLengthBytes;
}

std::uint8_t* EnvelopeRecorder::WriteHeader(std::uint8_t* at, int field_number, std::size_t body_bytes,
                                            std::int64_t send_time_ns) {
  // the Envelope's fields in field order, as the Messenger's sealer writes them
  at = PutTag(1, kVarint, at);
  at = PutVarint(1, at);
  at = PutTag(2, kFixed64, at);
  at = PutFixed64(session_id_, at);
  at = PutTag(3, kLengthDelimited, at);
  at = PutVarint(sender_bytes_, at);
  std::memcpy(at, sender_.data(), sender_bytes_);
  at += sender_bytes_;
  at = PutTag(4, kFixed64, at);
  at = PutFixed64(sender_epoch_, at);
  at = PutTag(5, kFixed64, at);
  at = PutFixed64(++sequence_, at);
  at = PutTag(6, kFixed64, at);
  at = PutFixed64(static_cast<std::uint64_t>(send_time_ns), at);
  at = PutTag(field_number, kLengthDelimited, at);
  return PutVarint(body_bytes, at);
}

void EnvelopeRecorder::Commit(std::size_t bytes) {
  PutLength(static_cast<std::uint32_t>(bytes), ring_.get() + claim_start_);
  const std::size_t head = head_.load(std::memory_order_relaxed);
  head_.store(head + claim_skip_ + Align8(kLengthBytes + bytes), std::memory_order_release);
  recorded_.fetch_add(1, std::memory_order_relaxed);
}

void EnvelopeRecorder::WriteWaiting() {
  std::size_t tail = tail_.load(std::memory_order_relaxed);
  const std::size_t head = head_.load(std::memory_order_acquire);
  bool wrote = false;
  while (tail != head) {
    const std::size_t at = tail % kRingBytes;
    const std::uint32_t bytes = GetLength(ring_.get() + at);
    if (bytes == kWrap) {
      tail += kRingBytes - at;
    } else {
      std::array<std::uint8_t, 10> length{};
      const std::size_t n = static_cast<std::size_t>(PutVarint(bytes, length.data()) - length.data());
      if (std::fwrite(length.data(), 1, n, file_) != n ||
          std::fwrite(ring_.get() + at + kLengthBytes, 1, bytes, file_) != bytes) {
        write_errors_.fetch_add(1, std::memory_order_relaxed);
      }
      tail += Align8(kLengthBytes + bytes);
      wrote = true;
    }
    tail_.store(tail, std::memory_order_release);
  }
  // small records sit in the file's buffer: a full disk shows only here
  if (wrote && std::fflush(file_) != 0) write_errors_.fetch_add(1, std::memory_order_relaxed);
}

}  // namespace haptex::services
