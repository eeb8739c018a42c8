#include "services/viewer/static_files.h"

#include <algorithm>
#include <array>
#include <system_error>
#include <utility>
#include <vector>

namespace haptex::viewer {
namespace {

int HexValue(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

std::optional<std::vector<std::string>> SplitSegments(std::string_view path) {
  std::vector<std::string> segments;
  std::size_t start = 0;
  while (start <= path.size()) {
    const std::size_t end = std::min(path.find('/', start), path.size());
    std::string segment(path.substr(start, end - start));
    // Empty segments would make "//etc" absolute; "." and ".." walk out of the root.
    if (segment.empty() || segment == "." || segment == ".." || segment.find('\\') != std::string::npos) {
      return std::nullopt;
    }
    segments.push_back(std::move(segment));
    start = end + 1;
  }
  return segments;
}

bool IsInside(const std::filesystem::path& file, const std::filesystem::path& root) {
  auto file_part = file.begin();
  for (const auto& root_part : root) {
    if (root_part.empty()) continue;  // a trailing separator
    if (file_part == file.end() || *file_part != root_part) return false;
    ++file_part;
  }
  return file_part != file.end();
}

}  // namespace

std::optional<std::string> PercentDecode(std::string_view text) {
  std::string decoded;
  decoded.reserve(text.size());
  for (std::size_t i = 0; i < text.size(); ++i) {
    char c = text[i];
    if (c == '%') {
      if (i + 2 >= text.size()) return std::nullopt;
      const int high = HexValue(text[i + 1]);
      const int low = HexValue(text[i + 2]);
      if (high < 0 || low < 0) return std::nullopt;
      c = static_cast<char>(high * 16 + low);
      i += 2;
    }
    if (c == '\0') return std::nullopt;
    decoded.push_back(c);
  }
  return decoded;
}

std::optional<std::string> ContentTypeOf(std::string_view file_name) {
  static constexpr std::array<std::pair<std::string_view, std::string_view>, 10> kTypes{{
      {".html", "text/html; charset=utf-8"},
      {".js", "text/javascript; charset=utf-8"},
      {".mjs", "text/javascript; charset=utf-8"},
      {".css", "text/css; charset=utf-8"},
      {".png", "image/png"},
      {".json", "application/json"},
      {".map", "application/json"},
      {".svg", "image/svg+xml"},
      {".ico", "image/x-icon"},
      {".txt", "text/plain; charset=utf-8"},
  }};
  const std::size_t dot = file_name.rfind('.');
  if (dot == std::string_view::npos) return std::nullopt;
  const std::string_view extension = file_name.substr(dot);
  for (const auto& [known, type] : kTypes) {
    if (extension == known) return std::string(type);
  }
  return std::nullopt;
}

std::optional<StaticFile> ResolveStaticFile(const StaticFileRoots& roots, std::string_view request_target) {
  const std::string_view path = request_target.substr(0, request_target.find_first_of("?#"));
  if (path.empty() || path.front() != '/') return std::nullopt;
  const std::optional<std::string> decoded = PercentDecode(path.substr(1));
  if (!decoded) return std::nullopt;
  std::optional<std::vector<std::string>> segments =
      decoded->empty() ? std::vector<std::string>{"index.html"} : SplitSegments(*decoded);
  if (!segments) return std::nullopt;

  std::filesystem::path root = roots.web_root;
  if (segments->front() == "three" && segments->size() > 1) {
    root = roots.three_root;
    segments->erase(segments->begin());
  }
  if (root.empty()) return std::nullopt;

  std::optional<std::string> content_type = ContentTypeOf(segments->back());
  if (!content_type) return std::nullopt;

  std::filesystem::path candidate = root;
  for (const std::string& segment : *segments) candidate /= segment;
  // Symlinks are followed, then the real file must still lie inside the real root.
  std::error_code error;
  const std::filesystem::path real_root = std::filesystem::canonical(root, error);
  if (error) return std::nullopt;
  const std::filesystem::path real_file = std::filesystem::canonical(candidate, error);
  if (error || !IsInside(real_file, real_root)) return std::nullopt;
  if (!std::filesystem::is_regular_file(real_file, error) || error) return std::nullopt;
  return StaticFile{real_file, std::move(*content_type)};
}

}  // namespace haptex::viewer
