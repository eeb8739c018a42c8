#pragma once
// Command-line values for the two directions of `haptex relay`: one value for both, or
// FORWARD,BACK. Every parser refuses garbage, NaN and infinity with std::invalid_argument
// naming the flag.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace haptex::cli {

template <typename T>
struct PerDirection {
  T forward{};
  T back{};
  bool differ = false;  // two values were given
};

/// One finite number ("1.5", "1e-3").
double ParseFiniteNumber(std::string_view flag, std::string_view text);
/// "V" or "F,B", each a finite number.
PerDirection<double> ParsePerDirectionNumber(std::string_view flag, std::string_view text);
/// "W" or "F,B".
PerDirection<std::string> ParsePerDirectionWord(std::string_view flag, std::string_view text);
/// "A,B,..." with min_count to max_count finite numbers.
std::vector<double> ParseNumberList(std::string_view flag, std::string_view text, std::size_t min_count,
                                    std::size_t max_count);
/// "S" (forward S, back S + 1, so the directions draw differently) or "F,B"; unsigned 64-bit.
PerDirection<std::uint64_t> ParsePerDirectionSeed(std::string_view flag, std::string_view text);

/// The name to put in an error about one direction's value: "--loss", or "--loss (back)"
/// when the directions were given apart.
std::string DirectionFlagName(std::string_view flag, bool differ, bool back);

}  // namespace haptex::cli
