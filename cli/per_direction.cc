#include "cli/per_direction.h"

#include <charconv>
#include <cmath>
#include <stdexcept>

namespace haptex::cli {
namespace {

std::vector<std::string_view> SplitCommas(std::string_view text) {
  std::vector<std::string_view> parts;
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = text.find(',', start);
    parts.push_back(text.substr(start, comma == std::string_view::npos ? comma : comma - start));
    if (comma == std::string_view::npos) return parts;
    start = comma + 1;
  }
}

std::vector<std::string_view> SplitDirections(std::string_view flag, std::string_view text) {
  const auto parts = SplitCommas(text);
  if (parts.size() > 2) {
    throw std::invalid_argument(std::string(flag) + ": one value for both directions or two as " +
                                "FORWARD,BACK, got '" + std::string(text) + "'");
  }
  return parts;
}

}  // namespace

double ParseFiniteNumber(std::string_view flag, std::string_view text) {
  double value = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || error != std::errc() || end != text.data() + text.size()) {
    throw std::invalid_argument(std::string(flag) + ": '" + std::string(text) + "' is not a number");
  }
  if (!std::isfinite(value)) {
    throw std::invalid_argument(std::string(flag) + ": '" + std::string(text) + "' is not a finite number");
  }
  return value;
}

PerDirection<double> ParsePerDirectionNumber(std::string_view flag, std::string_view text) {
  const auto parts = SplitDirections(flag, text);
  PerDirection<double> values;
  values.forward = ParseFiniteNumber(flag, parts[0]);
  values.differ = parts.size() == 2;
  values.back = values.differ ? ParseFiniteNumber(flag, parts[1]) : values.forward;
  return values;
}

PerDirection<std::string> ParsePerDirectionWord(std::string_view flag, std::string_view text) {
  const auto parts = SplitDirections(flag, text);
  for (const auto part : parts) {
    if (part.empty()) throw std::invalid_argument(std::string(flag) + ": empty value in '" + std::string(text) + "'");
  }
  PerDirection<std::string> values;
  values.forward = std::string(parts[0]);
  values.differ = parts.size() == 2;
  values.back = std::string(values.differ ? parts[1] : parts[0]);
  return values;
}

std::vector<double> ParseNumberList(std::string_view flag, std::string_view text, std::size_t min_count,
                                    std::size_t max_count) {
  const auto parts = SplitCommas(text);
  if (parts.size() < min_count || parts.size() > max_count) {
    throw std::invalid_argument(std::string(flag) + ": expected " + std::to_string(min_count) +
                                (max_count > min_count ? " to " + std::to_string(max_count) : "") +
                                " comma-separated numbers, got '" + std::string(text) + "'");
  }
  std::vector<double> values;
  for (const auto part : parts) values.push_back(ParseFiniteNumber(flag, part));
  return values;
}

PerDirection<std::uint64_t> ParsePerDirectionSeed(std::string_view flag, std::string_view text) {
  const auto parts = SplitDirections(flag, text);
  const auto parse = [&](std::string_view part) {
    std::uint64_t value = 0;
    const auto [end, error] = std::from_chars(part.data(), part.data() + part.size(), value);
    if (part.empty() || error != std::errc() || end != part.data() + part.size()) {
      throw std::invalid_argument(std::string(flag) + ": '" + std::string(part) +
                                  "' is not a whole number from 0 to 2^64 - 1");
    }
    return value;
  };
  PerDirection<std::uint64_t> values;
  values.forward = parse(parts[0]);
  values.differ = parts.size() == 2;
  values.back = values.differ ? parse(parts[1]) : values.forward + 1;
  return values;
}

std::string DirectionFlagName(std::string_view flag, bool differ, bool back) {
  if (!differ) return std::string(flag);
  return std::string(flag) + (back ? " (back)" : " (forward)");
}

}  // namespace haptex::cli
