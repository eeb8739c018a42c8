// Runs the fuzz target without libFuzzer: over every file of the given corpus folders, and over
// seeded mutations of each (bit flips, truncations, splices), so every build fuzzes a little.
//
// usage: envelope_corpus_replay MUTATIONS_PER_INPUT DIR...

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <random>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

int main(int argc, char** argv) {
  if (argc < 3) {
    std::cerr << "usage: " << argv[0] << " MUTATIONS_PER_INPUT DIR...\n";
    return 2;
  }
  const int mutations = std::atoi(argv[1]);
  std::vector<std::vector<std::uint8_t>> inputs;
  for (int i = 2; i < argc; ++i) {
    if (!std::filesystem::is_directory(argv[i])) continue;
    for (const auto& entry : std::filesystem::directory_iterator(argv[i])) {
      std::ifstream in(entry.path(), std::ios::binary);
      inputs.emplace_back(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
  }
  if (inputs.empty()) {
    std::cerr << "no corpus inputs found\n";
    return 1;
  }
  std::mt19937 rng(20081);
  std::size_t runs = 0;
  for (const auto& input : inputs) {
    LLVMFuzzerTestOneInput(input.data(), input.size());
    ++runs;
    for (int m = 0; m < mutations; ++m) {
      std::vector<std::uint8_t> mutated = input;
      switch (rng() % 4) {
        case 0:  // flip bits
          for (int k = 0; k < 1 + static_cast<int>(rng() % 8) && !mutated.empty(); ++k) {
            mutated[rng() % mutated.size()] ^= static_cast<std::uint8_t>(1u << (rng() % 8));
          }
          break;
        case 1:  // truncate
          mutated.resize(mutated.empty() ? 0 : rng() % mutated.size());
          break;
        case 2: {  // splice another input's tail
          const auto& other = inputs[rng() % inputs.size()];
          const std::size_t cut = mutated.empty() ? 0 : rng() % mutated.size();
          mutated.resize(cut);
          mutated.insert(mutated.end(), other.begin() + static_cast<std::ptrdiff_t>(other.size() / 2), other.end());
          break;
        }
        default:  // overwrite with random bytes
          for (auto& b : mutated) {
            if (rng() % 16 == 0) b = static_cast<std::uint8_t>(rng());
          }
      }
      LLVMFuzzerTestOneInput(mutated.data(), mutated.size());
      ++runs;
    }
  }
  std::cout << "fuzz replay: " << inputs.size() << " inputs, " << runs << " runs, no crash\n";
  return 0;
}
