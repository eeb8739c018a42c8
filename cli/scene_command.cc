#include "cli/scene_command.h"

#include <iostream>
#include <memory>
#include <vector>

#include "libs/scene/scene_loader.h"

namespace haptex::cli {

void AddSceneCommand(CLI::App& app, int* exit_code) {
  CLI::App* scene = app.add_subcommand("scene", "Scenes");
  scene->require_subcommand(1);
  auto files = std::make_shared<std::vector<std::string>>();
  CLI::App* check = scene->add_subcommand("check", "Validate scene files; errors as file:line:column");
  check->add_option("files", *files, "scene files (.textproto)")->required();
  check->callback([files, exit_code] {
    const scene::FabricDatabase fabrics(scene::FabricDatabase::DefaultDirectory());
    int failed = 0;
    for (const std::string& file : *files) {
      try {
        const scene::LoadedScene loaded = scene::LoadScene(file, fabrics);
        std::cout << file << ": ok (scene '" << loaded.scene.name() << "', fabric '" << loaded.fabric.name() << "')\n";
      } catch (const scene::TextProtoError& e) {
        std::cerr << e.what() << "\n";
        ++failed;
      }
    }
    *exit_code = failed == 0 ? 0 : 2;
  });
}

}  // namespace haptex::cli
