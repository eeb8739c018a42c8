#pragma once
// What `haptex view RUN_FOLDER` serves: the run's MCAP recording (checked whole before the page
// asks for it) and the session document, from the folder's own copy of its scene.

#include <string>

namespace haptex::viewer {

struct RunReplay {
  std::string session_json;
  std::string mcap_bytes;
  std::string scene_name;
  std::uint64_t messages = 0;
};

/// Throws std::runtime_error saying what is wrong: no such folder, not a haptex run (no run.mcap),
/// a recording that is truncated or not MCAP, a scene that no longer loads.
RunReplay LoadRunForReplay(const std::string& run_dir);

}  // namespace haptex::viewer
