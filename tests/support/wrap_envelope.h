#pragma once
// Envelopes for in-process tests of service loops: a body wrapped as a received datagram would
// carry it, from one sender (epoch 1) with the given sequence.

#include <cstdint>

#include <google/protobuf/descriptor.h>
#include <google/protobuf/message.h>

#include "haptex/v1/envelope.pb.h"
#include "libs/net/envelope_body.h"

namespace haptex::testing {

template <class Body>
v1::Envelope WrapEnvelope(const Body& body, std::uint64_t sequence, std::uint64_t sender_epoch = 1) {
  v1::Envelope envelope;
  envelope.set_version(1);
  envelope.set_sender("test");
  envelope.set_sender_epoch(sender_epoch);
  envelope.set_sequence(sequence);
  const auto* field = v1::Envelope::descriptor()->FindFieldByNumber(net::EnvelopeBody<Body>::kFieldNumber);
  envelope.GetReflection()->MutableMessage(&envelope, field)->CopyFrom(body);
  return envelope;
}

}  // namespace haptex::testing
