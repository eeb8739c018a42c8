// Fuzz target for the datagram decoder (libFuzzer entry point; also driven by
// envelope_corpus_replay.cc where libFuzzer is not available).
//
// Each input is opened twice: as a raw datagram (framing and MAC checks), and wrapped in valid
// framing with a correct MAC, so the parser and every check behind the MAC are reached too.

#include <cstddef>
#include <cstdint>
#include <vector>

#include <google/protobuf/arena.h>
#include <google/protobuf/stubs/logging.h>

#include "libs/net/envelope_codec.h"

namespace {

using haptex::net::DatagramMac;
using haptex::net::EnvelopeOpener;
using haptex::net::SessionKey;

const SessionKey& FuzzKey() {
  static const SessionKey key = SessionKey::FromHex("f0f1f2f3f4f5f6f7f8f9fafbfcfdfeff000102030405060708090a0b0c0d0e0f");
  return key;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // protobuf's own log lines (invalid UTF-8 and the like) are expected here, and noise
  static const bool quiet = [] {
    google::protobuf::SetLogHandler(nullptr);
    return true;
  }();
  (void)quiet;
  static EnvelopeOpener opener(FuzzKey(), /*session_id=*/7);
  static DatagramMac mac(FuzzKey());
  static std::vector<char> block(1 << 20);
  static google::protobuf::Arena arena = [] {
    google::protobuf::ArenaOptions options;
    options.initial_block = block.data();
    options.initial_block_size = block.size();
    return google::protobuf::Arena(options);
  }();

  arena.Reset();
  opener.Open({data, size}, google::protobuf::Arena::CreateMessage<haptex::v1::Envelope>(&arena));

  if (size + haptex::net::kDatagramOverheadBytes > opener.max_datagram_bytes()) return 0;
  std::vector<std::uint8_t> authentic(haptex::net::kDatagramMagic.begin(), haptex::net::kDatagramMagic.end());
  authentic.resize(haptex::net::kDatagramHeaderBytes);  // fixed nonce: deterministic runs
  authentic.insert(authentic.end(), data, data + size);
  authentic.resize(authentic.size() + DatagramMac::kTagBytes);
  const std::size_t signed_bytes = authentic.size() - DatagramMac::kTagBytes;
  mac.Compute({authentic.data(), signed_bytes}, authentic.data() + haptex::net::kDatagramMagic.size(),
              authentic.data() + signed_bytes);
  arena.Reset();
  opener.Open(authentic, google::protobuf::Arena::CreateMessage<haptex::v1::Envelope>(&arena));
  return 0;
}
