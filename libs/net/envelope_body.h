#pragma once
// Maps each Envelope body type to its field number in the Envelope's oneof.

#include "haptex/v1/envelope.pb.h"

namespace haptex::net {

template <class Body>
struct EnvelopeBody;  // undefined: not an Envelope body

#define HAPTEX_ENVELOPE_BODY(Type, Field)                                    \
  template <>                                                                \
  struct EnvelopeBody<v1::Type> {                                            \
    static constexpr int kFieldNumber = v1::Envelope::k##Field##FieldNumber; \
    static constexpr v1::Envelope::BodyCase kCase = v1::Envelope::k##Field;  \
  }

HAPTEX_ENVELOPE_BODY(FingerStates, FingerStates);
HAPTEX_ENVELOPE_BODY(ForceModel, ForceModel);
HAPTEX_ENVELOPE_BODY(LocalPatch, LocalPatch);
HAPTEX_ENVELOPE_BODY(PatchResult, PatchResult);
HAPTEX_ENVELOPE_BODY(TouchTrace, TouchTrace);
HAPTEX_ENVELOPE_BODY(PinFrame, PinFrame);
HAPTEX_ENVELOPE_BODY(ClothFrame, ClothFrame);
HAPTEX_ENVELOPE_BODY(Health, Health);
HAPTEX_ENVELOPE_BODY(Control, Control);
HAPTEX_ENVELOPE_BODY(NetProbe, NetProbe);

#undef HAPTEX_ENVELOPE_BODY

}  // namespace haptex::net
