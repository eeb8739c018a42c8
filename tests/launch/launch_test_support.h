#pragma once
// Scenes for the launcher's tests: the shipped ones, and scenes written from text.

#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <string>
#include <unistd.h>

#include "libs/scene/scene_loader.h"
#include "tests/support/test_paths.h"

namespace haptex::launch::testing {

inline scene::FabricDatabase Fabrics() {
  return scene::FabricDatabase(haptex::testing::SourceDir() + "/data/fabrics");
}

inline std::string ShippedScenePath(const std::string& name) {
  return haptex::testing::SourceDir() + "/launch/scenes/" + name + ".textproto";
}

inline v1::Scene ShippedScene(const std::string& name) {
  return scene::LoadScene(ShippedScenePath(name), Fabrics()).scene;
}

/// Parses and validates scene text (throws scene::TextProtoError).
inline v1::Scene SceneFromText(const std::string& text) {
  return scene::ParseScene(text, "test.textproto", Fabrics()).scene;
}

inline std::string ReadText(const std::string& path) {
  std::ifstream in(path);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

inline void WriteText(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

/// A fresh folder under the test temp dir.
inline std::string FreshDir(const std::string& name) {
  const std::string dir = ::testing::TempDir() + "/" + name + "_" + std::to_string(getpid());
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace haptex::launch::testing
