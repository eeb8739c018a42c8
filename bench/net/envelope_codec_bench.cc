// Cost of sealing and opening one datagram (MAC included), per envelope size.
//   build/bench/net/envelope_codec_bench

#include <benchmark/benchmark.h>

#include <google/protobuf/arena.h>

#include <vector>

#include "libs/net/envelope_codec.h"

namespace haptex::net {
namespace {

struct Fixture {
  explicit Fixture(std::size_t envelope_bytes)
      : key(SessionKey::Generate()),
        sealer(key, {"local_contact", 1, 1}),
        opener(key, 1),
        buffer(kMaxUdpPayloadBytes),
        block(1 << 20) {
    // pad the body so the whole datagram has about the requested size
    const std::size_t overhead = sealer.Seal(probe, 0, "receiver", buffer);
    probe.set_padding(std::string(envelope_bytes > overhead + 3 ? envelope_bytes - overhead - 3 : 0, 'x'));
    google::protobuf::ArenaOptions options;
    options.initial_block = block.data();
    options.initial_block_size = block.size();
    arena = std::make_unique<google::protobuf::Arena>(options);
  }
  SessionKey key;
  EnvelopeSealer sealer;
  EnvelopeOpener opener;
  std::vector<std::uint8_t> buffer;
  std::vector<char> block;
  std::unique_ptr<google::protobuf::Arena> arena;
  v1::NetProbe probe;
};

void BM_SealAndOpen(benchmark::State& state) {
  Fixture f(static_cast<std::size_t>(state.range(0)));
  std::size_t bytes = 0;
  for (auto _ : state) {
    bytes = f.sealer.Seal(f.probe, 0, "receiver", f.buffer);
    f.arena->Reset();
    auto* envelope = google::protobuf::Arena::CreateMessage<v1::Envelope>(f.arena.get());
    if (f.opener.Open({f.buffer.data(), bytes}, envelope) != DropReason::kNone) {
      state.SkipWithError("open failed");
      break;
    }
    benchmark::DoNotOptimize(envelope);
  }
  state.counters["datagram_bytes"] = static_cast<double>(bytes);
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * bytes));
}
BENCHMARK(BM_SealAndOpen)->Arg(128)->Arg(1024)->Arg(8192);

void BM_MacOnly(benchmark::State& state) {
  const DatagramMac mac(SessionKey::Generate());
  std::vector<std::uint8_t> data(static_cast<std::size_t>(state.range(0)), 0x5a);
  DatagramMac::Nonce nonce;
  DatagramMac::Tag tag;
  for (auto _ : state) {
    DatagramMac::NewNonce(nonce.data());
    mac.Compute(data, nonce.data(), tag.data());
    benchmark::DoNotOptimize(tag);
  }
}
BENCHMARK(BM_MacOnly)->Arg(1024);

void BM_RejectGarbage(benchmark::State& state) {
  Fixture f(1024);
  const std::size_t bytes = f.sealer.Seal(f.probe, 0, "receiver", f.buffer);
  f.buffer[bytes / 2] ^= 1;  // fails the MAC: the cost of a flood of forged datagrams
  v1::Envelope envelope;
  for (auto _ : state) {
    benchmark::DoNotOptimize(f.opener.Open({f.buffer.data(), bytes}, &envelope));
  }
}
BENCHMARK(BM_RejectGarbage);

}  // namespace
}  // namespace haptex::net

BENCHMARK_MAIN();
