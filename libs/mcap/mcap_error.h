#pragma once
// What a reader throws on a file that is missing, cut short or not MCAP: what is wrong and where.

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>

namespace haptex::mcap {

class McapError : public std::runtime_error {
 public:
  /// `offset`: where in the file [bytes from its start] the problem was found.
  McapError(const std::string& reason, std::optional<std::uint64_t> offset = std::nullopt)
      : std::runtime_error(Text(reason, offset)), reason_(reason), offset_(offset) {}

  const std::string& reason() const { return reason_; }
  std::optional<std::uint64_t> offset() const { return offset_; }
  /// The same error, naming the file it is about.
  McapError In(const std::string& path) const { return McapError(path + ": " + reason_, offset_); }

 private:
  static std::string Text(const std::string& reason, std::optional<std::uint64_t> offset) {
    return "MCAP: " + reason + (offset ? " (at byte " + std::to_string(*offset) + ")" : std::string());
  }
  std::string reason_;
  std::optional<std::uint64_t> offset_;
};

}  // namespace haptex::mcap
