#pragma once
// An Outbox for in-process tests of service loops: it keeps every message a loop sends (peer, body
// type, bytes), or, with capture off, only counts them (no allocation, for the warmed-up tick of an
// allocation test).

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "services/common/outbox.h"

namespace haptex::testing {

class CapturedOutbox final : public services::Outbox {
 public:
  struct Sent {
    services::PeerId peer = 0;
    int body_field_number = 0;
    std::string bytes;
  };

  /// false: count only (nothing kept, nothing allocated).
  bool capture = true;
  /// true: every send fails (a refusing socket).
  bool refuse = false;

  /// The messages of type Body sent to `peer`, in order.
  template <class Body>
  std::vector<Body> Of(services::PeerId peer) const {
    std::vector<Body> out;
    for (const Sent& s : sent_) {
      if (s.peer != peer || s.body_field_number != net::EnvelopeBody<Body>::kFieldNumber) continue;
      out.emplace_back();
      out.back().ParseFromString(s.bytes);
    }
    return out;
  }
  /// How many Body messages were sent to anyone, captured or not.
  template <class Body>
  std::uint64_t Count() const {
    return counts_[static_cast<std::size_t>(net::EnvelopeBody<Body>::kFieldNumber)];
  }
  const std::vector<Sent>& sent() const { return sent_; }
  /// Messages recorded without being sent (Outbox::Record), by body type.
  template <class Body>
  std::uint64_t Recorded() const {
    return recorded_[static_cast<std::size_t>(net::EnvelopeBody<Body>::kFieldNumber)];
  }
  void Clear() {
    sent_.clear();
    counts_.fill(0);
    recorded_.fill(0);
  }

 protected:
  bool SendBody(services::PeerId peer, const google::protobuf::MessageLite& body, int body_field_number) override {
    ++counts_[static_cast<std::size_t>(body_field_number)];
    if (capture) sent_.push_back({peer, body_field_number, body.SerializeAsString()});
    return !refuse;
  }
  void RecordBody(const google::protobuf::MessageLite& /*body*/, int body_field_number) override {
    ++recorded_[static_cast<std::size_t>(body_field_number)];
  }

 private:
  std::vector<Sent> sent_;
  std::array<std::uint64_t, 64> counts_{};
  std::array<std::uint64_t, 64> recorded_{};
};

}  // namespace haptex::testing
