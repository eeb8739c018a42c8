#!/usr/bin/env bash
# Builds the envelope fuzz target with clang's libFuzzer (+ASan, UBSan) and runs it for a bounded
# time over the seed corpus. Exits 77 (ctest: skipped) when clang or libFuzzer is missing.
# usage: run_libfuzzer.sh SOURCE_DIR BUILD_DIR SECONDS
set -euo pipefail
src=$1 build=$2 seconds=$3
clang=$(command -v clang++ || command -v clang++-14 || true)
if [[ -z "$clang" ]]; then
  echo "clang++ not found: libFuzzer run skipped (the corpus replay test still runs)"; exit 77
fi
out=$build/fuzz-libfuzzer
mkdir -p "$out/corpus"
cp -n "$build"/tests/fuzz/seeds/* "$out/corpus/" 2>/dev/null || true
sources=("$src"/tests/fuzz/envelope_open_fuzz.cc "$src"/libs/net/{drop_reason,sodium_init,session_key,datagram_mac,replay_window,envelope_codec}.cc "$build"/proto/haptex/v1/*.pb.cc)
inputs=("${sources[@]}" "$src"/libs/net/*.h "$build"/proto/haptex/v1/*.pb.h)
if [[ ! -x "$out/envelope_open_fuzz" ]] || [[ -n "$(find "${inputs[@]}" -newer "$out/envelope_open_fuzz" 2>/dev/null | head -1)" ]]; then
  if ! echo 'extern "C" int LLVMFuzzerTestOneInput(const unsigned char*, unsigned long){return 0;}' \
      | "$clang" -x c++ -fsanitize=fuzzer - -o "$out/probe" 2>/dev/null; then
    echo "clang has no libFuzzer runtime: libFuzzer run skipped"; exit 77
  fi
  echo "building $out/envelope_open_fuzz with $clang"
  "$clang" -std=c++20 -O1 -g -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined \
    -I"$src" -I"$build/proto" "${sources[@]}" -lprotobuf -lsodium -lpthread -o "$out/envelope_open_fuzz"
fi
"$out/envelope_open_fuzz" -max_total_time="$seconds" -max_len=4096 -print_final_stats=1 \
  -artifact_prefix="$out/" "$out/corpus" 2>&1 | tail -n 25
