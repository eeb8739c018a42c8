#pragma once
// Where a run's files go. A scene's name is user text: it becomes one safe path component (a slug),
// and each launch gets a folder of its own, created exclusively beside earlier ones.

#include <cstddef>
#include <string>
#include <string_view>

namespace haptex::launch {

/// The longest slug; longer names are cut (a run folder's name is for people, not a key).
inline constexpr std::size_t kMaxRunSlugBytes = 64;

/// `name` as one path component: ASCII letters, digits, '-', '_' and '.' are kept, every other byte
/// (separators, quotes, control characters, non-ASCII, invalid UTF-8) becomes '_', runs of '_'
/// become one, at most kMaxRunSlugBytes; never empty ("scene") and never starting with '.' (so never
/// "." or "..", nor hidden).
std::string RunFolderSlug(std::string_view name);

/// The default folder name: SLUG-STAMP, or SLUG-STAMP-HOSTSLUG for a host of a multi-host scene.
std::string RunFolderStem(std::string_view scene_name, std::string_view stamp, std::string_view host);

/// Creates parent (if needed), then a new folder parent/STEM, or parent/STEM-2, parent/STEM-3, ...
/// when that name is taken: each mkdir fails if the folder exists, so two launches never share one.
/// STEM is made a slug first, so the folder is always a direct child of parent. Returns its path.
/// @throws std::runtime_error when no folder can be created.
std::string CreateUniqueRunFolder(const std::string& parent, std::string_view stem);

/// Writes `text` as the whole of the file at `path`. A run folder's record must not be lost without
/// a word: a full disk, or a folder where the file should be, fails here with the system's reason.
/// @throws std::runtime_error "cannot write PATH: REASON".
void WriteRunFile(const std::string& path, std::string_view text);

}  // namespace haptex::launch
