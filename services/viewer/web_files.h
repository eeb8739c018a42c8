#pragma once
// Where the page and three.js are: web/viewer and web/node_modules/three of the source tree (three
// is installed there by scripts/setup), or under HAPTEX_WEB_DIR when set.

#include <string>

namespace haptex::viewer {

struct WebFiles {
  std::string page_dir;   ///< index.html and the page's modules
  std::string three_dir;  ///< the three npm package (build/, examples/jsm/)
};

/// Throws std::runtime_error naming what is missing and how to get it.
WebFiles FindWebFiles();

}  // namespace haptex::viewer
