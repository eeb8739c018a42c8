#include "libs/net/envelope_codec.h"

#include <google/protobuf/io/coded_stream.h>

#include <algorithm>
#include <stdexcept>

namespace haptex::net {
namespace {

using google::protobuf::io::CodedOutputStream;

constexpr std::uint32_t kWireVarint = 0;
constexpr std::uint32_t kWireFixed64 = 1;
constexpr std::uint32_t kWireLengthDelimited = 2;

constexpr std::uint32_t Tag(int field, std::uint32_t wire_type) {
  return (static_cast<std::uint32_t>(field) << 3) | wire_type;
}

// Upper bound of the Envelope header fields (everything but the body) on the wire.
constexpr std::size_t kHeaderBoundBytes = 6 /*version*/ + 9 /*session*/ +
                                          2 * (2 + SenderTable::kMaxNameBytes) /*sender, destination*/ +
                                          9 * 3 /*epoch, sequence, time*/;

}  // namespace

EnvelopeSealer::EnvelopeSealer(const SessionKey& key, SenderIdentity identity)
    : mac_(key), identity_(std::move(identity)) {
  if (identity_.name.empty() || identity_.name.size() > SenderTable::kMaxNameBytes) {
    throw std::invalid_argument("sender name must have 1 to " + std::to_string(SenderTable::kMaxNameBytes) +
                                " characters");
  }
  if (identity_.epoch == 0) throw std::invalid_argument("sender epoch must be > 0");
  if (identity_.session_id == 0) throw std::invalid_argument("session id must be > 0");
}

std::size_t EnvelopeSealer::SealBody(const google::protobuf::MessageLite& body, int body_field_number,
                                     std::int64_t send_time_ns, std::string_view destination,
                                     std::span<std::uint8_t> out) {
  if (destination.size() > SenderTable::kMaxNameBytes) return 0;
  const std::size_t body_bytes = body.ByteSizeLong();
  const std::size_t bound = kDatagramOverheadBytes + kHeaderBoundBytes + 6 + body_bytes;
  if (bound > out.size() || body_bytes > kMaxUdpPayloadBytes) return 0;

  // The Envelope is written field by field, exactly as protobuf would serialize it with the body
  // set, so the body never has to be copied into an Envelope object.
  std::uint8_t* p = std::copy(kDatagramMagic.begin(), kDatagramMagic.end(), out.data());
  std::uint8_t* nonce = p;
  nonces_.Next(nonce);
  p += DatagramMac::kNonceBytes;
  p = CodedOutputStream::WriteTagToArray(Tag(v1::Envelope::kVersionFieldNumber, kWireVarint), p);
  p = CodedOutputStream::WriteVarint32ToArray(kEnvelopeVersion, p);
  p = CodedOutputStream::WriteTagToArray(Tag(v1::Envelope::kSessionIdFieldNumber, kWireFixed64), p);
  p = CodedOutputStream::WriteLittleEndian64ToArray(identity_.session_id, p);
  p = CodedOutputStream::WriteTagToArray(Tag(v1::Envelope::kSenderFieldNumber, kWireLengthDelimited), p);
  p = CodedOutputStream::WriteVarint32ToArray(static_cast<std::uint32_t>(identity_.name.size()), p);
  p = CodedOutputStream::WriteRawToArray(identity_.name.data(), static_cast<int>(identity_.name.size()), p);
  p = CodedOutputStream::WriteTagToArray(Tag(v1::Envelope::kSenderEpochFieldNumber, kWireFixed64), p);
  p = CodedOutputStream::WriteLittleEndian64ToArray(identity_.epoch, p);
  p = CodedOutputStream::WriteTagToArray(Tag(v1::Envelope::kSequenceFieldNumber, kWireFixed64), p);
  p = CodedOutputStream::WriteLittleEndian64ToArray(next_sequence_, p);
  p = CodedOutputStream::WriteTagToArray(Tag(v1::Envelope::kSendTimeNsFieldNumber, kWireFixed64), p);
  p = CodedOutputStream::WriteLittleEndian64ToArray(static_cast<std::uint64_t>(send_time_ns), p);
  if (!destination.empty()) {
    p = CodedOutputStream::WriteTagToArray(Tag(v1::Envelope::kDestinationFieldNumber, kWireLengthDelimited), p);
    p = CodedOutputStream::WriteVarint32ToArray(static_cast<std::uint32_t>(destination.size()), p);
    p = CodedOutputStream::WriteRawToArray(destination.data(), static_cast<int>(destination.size()), p);
  }
  p = CodedOutputStream::WriteTagToArray(Tag(body_field_number, kWireLengthDelimited), p);
  p = CodedOutputStream::WriteVarint32ToArray(static_cast<std::uint32_t>(body_bytes), p);
  p = body.SerializeWithCachedSizesToArray(p);

  const auto signed_bytes = static_cast<std::size_t>(p - out.data());
  mac_.Compute(std::span<const std::uint8_t>(out.data(), signed_bytes), nonce, p);
  ++next_sequence_;
  return signed_bytes + DatagramMac::kTagBytes;
}

std::size_t EnvelopeSealer::SealRaw(const v1::Envelope& envelope, std::span<std::uint8_t> out) {
  const std::size_t envelope_bytes = envelope.ByteSizeLong();
  const std::size_t total = kDatagramOverheadBytes + envelope_bytes;
  if (total > out.size()) return 0;
  std::uint8_t* p = std::copy(kDatagramMagic.begin(), kDatagramMagic.end(), out.data());
  std::uint8_t* nonce = p;
  nonces_.Next(nonce);
  p = envelope.SerializeWithCachedSizesToArray(p + DatagramMac::kNonceBytes);
  const auto signed_bytes = static_cast<std::size_t>(p - out.data());
  mac_.Compute(std::span<const std::uint8_t>(out.data(), signed_bytes), nonce, p);
  return total;
}

EnvelopeOpener::EnvelopeOpener(const SessionKey& key, std::uint64_t session_id, std::size_t max_datagram_bytes)
    : mac_(key), session_id_(session_id), max_datagram_bytes_(max_datagram_bytes) {
  if (session_id == 0) throw std::invalid_argument("session id must be > 0");
  if (max_datagram_bytes < kDatagramOverheadBytes || max_datagram_bytes > kMaxUdpPayloadBytes) {
    throw std::invalid_argument("max datagram size must be between " + std::to_string(kDatagramOverheadBytes) +
                                " and " + std::to_string(kMaxUdpPayloadBytes) + " bytes");
  }
}

DropReason EnvelopeOpener::Open(std::span<const std::uint8_t> datagram, v1::Envelope* envelope) {
  const DropReason reason = Classify(datagram, envelope);
  counters_.Add(reason);
  return reason;
}

DropReason EnvelopeOpener::Classify(std::span<const std::uint8_t> datagram, v1::Envelope* envelope) {
  if (datagram.size() < kDatagramOverheadBytes) return DropReason::kTruncated;
  if (datagram.size() > max_datagram_bytes_) return DropReason::kOversized;
  if (!std::equal(kDatagramMagic.begin(), kDatagramMagic.end(), datagram.begin())) {
    return DropReason::kBadMagic;
  }
  const std::size_t signed_bytes = datagram.size() - DatagramMac::kTagBytes;
  if (!mac_.Verify(datagram.first(signed_bytes), datagram.data() + kDatagramMagic.size(),
                   datagram.data() + signed_bytes)) {
    return DropReason::kBadMac;
  }
  const auto payload = datagram.subspan(kDatagramHeaderBytes, signed_bytes - kDatagramHeaderBytes);
  if (!envelope->ParseFromArray(payload.data(), static_cast<int>(payload.size()))) {
    return DropReason::kUnparsable;
  }
  if (envelope->version() != kEnvelopeVersion) return DropReason::kWrongVersion;
  if (envelope->session_id() != session_id_) return DropReason::kWrongSession;
  if (!destinations_.empty() &&
      std::find(destinations_.begin(), destinations_.end(), envelope->destination()) == destinations_.end()) {
    return DropReason::kWrongDestination;
  }
  if (envelope->body_case() == v1::Envelope::BODY_NOT_SET) return DropReason::kUnknownBody;
  return senders_.Check(envelope->sender(), envelope->sender_epoch(), envelope->sequence());
}

}  // namespace haptex::net
