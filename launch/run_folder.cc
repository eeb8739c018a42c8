#include "launch/run_folder.h"

#include <sys/stat.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>

namespace haptex::launch {
namespace {

bool SafeByte(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' || c == '_' || c == '.';
}

// Attempts beyond this mean something else is wrong (a folder full of runs of one second).
constexpr int kMaxSuffix = 1000;

}  // namespace

std::string RunFolderSlug(std::string_view name) {
  std::string slug;
  for (const char c : name) {
    if (slug.size() >= kMaxRunSlugBytes) break;
    const char safe = SafeByte(c) ? c : '_';
    if (safe == '_' && !slug.empty() && slug.back() == '_') continue;
    if (safe == '.' && slug.empty()) {
      slug += '_';  // no ".", "..", nor a hidden folder
      continue;
    }
    slug += safe;
  }
  return slug.empty() ? std::string("scene") : slug;
}

std::string RunFolderStem(std::string_view scene_name, std::string_view stamp, std::string_view host) {
  std::string stem = RunFolderSlug(scene_name) + "-" + RunFolderSlug(stamp);
  if (!host.empty()) stem += "-" + RunFolderSlug(host);
  return stem;
}

std::string CreateUniqueRunFolder(const std::string& parent, std::string_view stem) {
  std::filesystem::create_directories(parent);
  const std::string base = RunFolderSlug(stem);
  for (int n = 1; n <= kMaxSuffix; ++n) {
    const std::string path = parent + "/" + (n == 1 ? base : base + "-" + std::to_string(n));
    if (mkdir(path.c_str(), 0755) == 0) return path;
    if (errno != EEXIST) {
      throw std::runtime_error("cannot create the run folder " + path + ": " + std::strerror(errno));
    }
  }
  throw std::runtime_error("cannot create a run folder in " + parent + ": " + base + " and " +
                           std::to_string(kMaxSuffix - 1) + " suffixed names are taken");
}

void WriteRunFile(const std::string& path, std::string_view text) {
  auto fail = [&](int error) { throw std::runtime_error("cannot write " + path + ": " + std::strerror(error)); };
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) fail(errno);
  // a full disk may only show when the buffer is flushed, or even at close
  const bool written = std::fwrite(text.data(), 1, text.size(), file) == text.size() && std::fflush(file) == 0;
  const int write_error = errno;
  const bool closed = std::fclose(file) == 0;
  if (!written) fail(write_error);
  if (!closed) fail(errno);
}

}  // namespace haptex::launch
