#pragma once
// Where a service loop's Write step puts the messages it sends. The service process sends them
// through its Messenger (and records them with --record: ServiceContext); an in-process test keeps
// them (tests/support/captured_outbox.h). Sending never blocks or allocates once warmed up.

#include <cstddef>

#include <google/protobuf/message_lite.h>

#include "libs/net/envelope_body.h"

namespace haptex::services {

/// A peer as the Messenger numbers it (net::Messenger::PeerId).
using PeerId = std::size_t;

class Outbox {
 public:
  virtual ~Outbox() = default;

  /// Sends `body` to `peer`; false when it could not go (too large, socket refused), which the
  /// loop counts.
  template <class Body>
  bool Send(PeerId peer, const Body& body) {
    return SendBody(peer, body, net::EnvelopeBody<Body>::kFieldNumber);
  }
  /// Records `body` as sent, without sending it (a run's recording of what nobody receives live).
  template <class Body>
  void Record(const Body& body) {
    RecordBody(body, net::EnvelopeBody<Body>::kFieldNumber);
  }

 protected:
  /// `body_field_number`: the body's field in the Envelope oneof.
  virtual bool SendBody(PeerId peer, const google::protobuf::MessageLite& body, int body_field_number) = 0;
  /// Nothing where there is no recording.
  virtual void RecordBody(const google::protobuf::MessageLite& /*body*/, int /*body_field_number*/) {}
};

}  // namespace haptex::services
