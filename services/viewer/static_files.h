#pragma once
// Which file a plain HTTP GET serves: the viewer page and its scripts from a web root, three.js
// from its own root. A request names a file only inside its root; everything else is refused.

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

namespace haptex::viewer {

struct StaticFileRoots {
  std::filesystem::path web_root;    // "/" is <web_root>/index.html, "/a/b.js" is <web_root>/a/b.js
  std::filesystem::path three_root;  // "/three/a.js" is <three_root>/a.js
};

struct StaticFile {
  std::filesystem::path path;  // canonical, inside its root
  std::string content_type;
};

/// The file a GET of `request_target` (path with optional query) serves, or nullopt when it names
/// none: an empty root, a malformed or NUL percent escape, a `.`/`..`/empty segment, a backslash,
/// a file outside its root after resolving symlinks, something that is not a regular file, or an
/// extension without a known content type.
std::optional<StaticFile> ResolveStaticFile(const StaticFileRoots& roots, std::string_view request_target);

/// The Content-Type of a file name by its extension (html, js/mjs, css, png, json/map, svg, ico,
/// txt), or nullopt for any other.
std::optional<std::string> ContentTypeOf(std::string_view file_name);

/// `%XX` escapes decoded; nullopt for a malformed escape or a NUL byte, escaped or not.
std::optional<std::string> PercentDecode(std::string_view text);

}  // namespace haptex::viewer
