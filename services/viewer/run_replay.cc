#include "services/viewer/run_replay.h"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "libs/codec/envelope_channel.h"
#include "libs/mcap/mcap_reader.h"
#include "services/viewer/session_info.h"

namespace haptex::viewer {
namespace {

namespace fs = std::filesystem;

std::string ReadWhole(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path.string());
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

// The scene the run ran: the folder's own copy, else the file summary.json names.
scene::LoadedScene RunScene(const fs::path& run) {
  fs::path scene_path = run / "scene.textproto";
  if (!fs::is_regular_file(scene_path) && fs::is_regular_file(run / "summary.json")) {
    try {
      const auto summary = nlohmann::json::parse(ReadWhole(run / "summary.json"));
      if (summary.contains("scene_path") && summary["scene_path"].is_string()) {
        scene_path = summary["scene_path"].get<std::string>();
      }
    } catch (const nlohmann::json::exception& e) {
      throw std::runtime_error((run / "summary.json").string() + " is not JSON: " + e.what());
    }
  }
  if (!fs::is_regular_file(scene_path)) {
    throw std::runtime_error(run.string() + " has no scene.textproto and its summary.json names none that exists");
  }
  try {
    return scene::LoadScene(scene_path.string(), scene::FabricDatabase(scene::FabricDatabase::DefaultDirectory()));
  } catch (const std::exception& e) {
    throw std::runtime_error("the run's scene does not load: " + std::string(e.what()));
  }
}

}  // namespace

RunReplay LoadRunForReplay(const std::string& run_dir) {
  const fs::path run(run_dir);
  if (!fs::is_directory(run)) throw std::runtime_error("no such run folder: " + run_dir);
  const fs::path mcap_path = run / "run.mcap";
  if (!fs::is_regular_file(mcap_path)) {
    throw std::runtime_error(run_dir + " is not a haptex run folder: it has no run.mcap");
  }
  RunReplay replay;
  replay.mcap_bytes = ReadWhole(mcap_path);
  mcap::McapFile file;
  try {
    // checked whole here, so the page never meets a broken file
    file = mcap::ReadMcap(replay.mcap_bytes);
  } catch (const mcap::McapError& e) {
    throw std::runtime_error(e.In(mcap_path.string()).what());
  }
  // ... nor one of another program: every channel must be one a haptex run records
  for (const mcap::Channel& c : file.channels) {
    const mcap::Schema* schema = file.FindSchema(c.schema_id);
    std::string why;
    if (codec::EnvelopeChannelOf(c.topic, c.message_encoding, schema ? schema->name : "",
                                 schema ? schema->encoding : "", &why)
            .body == nullptr) {
      throw std::runtime_error(mcap_path.string() + " is not a haptex run's recording: channel " + c.topic + ": " +
                               why);
    }
  }
  replay.messages = file.messages.size();
  const scene::LoadedScene scene = RunScene(run);
  replay.scene_name = scene.scene.name();
  replay.session_json = SessionJson(scene, "/run.mcap");
  return replay;
}

}  // namespace haptex::viewer
