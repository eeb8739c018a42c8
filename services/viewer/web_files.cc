#include "services/viewer/web_files.h"

#include <cstdlib>
#include <filesystem>
#include <stdexcept>

namespace haptex::viewer {

WebFiles FindWebFiles() {
  const char* env = std::getenv("HAPTEX_WEB_DIR");
  const std::string web = env != nullptr && *env != '\0' ? std::string(env) : std::string(HAPTEX_DEFAULT_WEB_DIR);
  WebFiles files{web + "/viewer", web + "/node_modules/three"};
  if (!std::filesystem::is_regular_file(files.page_dir + "/index.html")) {
    throw std::runtime_error("the viewer page is missing: no " + files.page_dir + "/index.html");
  }
  if (!std::filesystem::is_regular_file(files.three_dir + "/build/three.module.js")) {
    throw std::runtime_error("three.js is missing (" + files.three_dir +
                             "/build/three.module.js): run scripts/setup, which installs web/'s npm packages");
  }
  return files;
}

}  // namespace haptex::viewer
