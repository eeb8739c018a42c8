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

}  // namespace

EnvelopeRecorder::EnvelopeRecorder(const std::string& path, std::string_view sender,
                                   std::uint64_t sender_epoch, std::uint64_t session_id)
    : sender_epoch_(sender_epoch), session_id_(session_id) {
  if (sender.size() > sender_.size()) throw std::invalid_argument("recorder: sender name too long");
  std::memcpy(sender_.data(), sender.data(), sender.size());
  sender_bytes_ = sender.size();
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
  if (body_bytes + 64 + sender_bytes_ > kSlotBytes) {
    dropped_.fetch_add(1, std::memory_order_relaxed);
    return nullptr;
  }
  const std::size_t head = head_.load(std::memory_order_relaxed);
  if (head - tail_.load(std::memory_order_acquire) == kSlots) {
    dropped_.fetch_add(1, std::memory_order_relaxed);
    return nullptr;
  }
  return slots_[head & (kSlots - 1)].data.data();
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
  const std::size_t head = head_.load(std::memory_order_relaxed);
  slots_[head & (kSlots - 1)].bytes = static_cast<std::uint32_t>(bytes);
  head_.store(head + 1, std::memory_order_release);
  recorded_.fetch_add(1, std::memory_order_relaxed);
}

void EnvelopeRecorder::WriteWaiting() {
  std::size_t tail = tail_.load(std::memory_order_relaxed);
  const std::size_t head = head_.load(std::memory_order_acquire);
  bool wrote = false;
  for (; tail != head; ++tail) {
    const Slot& slot = slots_[tail & (kSlots - 1)];
    std::array<std::uint8_t, 10> length{};
    const std::size_t n = static_cast<std::size_t>(PutVarint(slot.bytes, length.data()) - length.data());
    if (std::fwrite(length.data(), 1, n, file_) != n ||
        std::fwrite(slot.data.data(), 1, slot.bytes, file_) != slot.bytes) {
      write_errors_.fetch_add(1, std::memory_order_relaxed);
    }
    tail_.store(tail + 1, std::memory_order_release);
    wrote = true;
  }
  if (wrote) std::fflush(file_);
}

}  // namespace haptex::services
