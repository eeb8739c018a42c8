#pragma once
// Loading a scene: parse, resolve its fabric, validate every field. Any problem refuses the whole
// scene with file:line:column and what is wrong.

#include <string>
#include <vector>

#include "haptex/v1/scene.pb.h"
#include "libs/scene/fabric_database.h"
#include "libs/scene/text_proto.h"

namespace haptex::scene {

struct LoadedScene {
  std::string path;
  v1::Scene scene;
  v1::Fabric fabric;  // the database entry or the inline fabric
};

/// Semantic checks of a parsed scene (fabric data included). Empty when usable.
std::vector<TextIssue> ValidateScene(const v1::Scene& scene, const FieldLocator& where, const FabricDatabase& fabrics);

/// Throws TextProtoError listing every problem.
LoadedScene LoadScene(const std::string& path, const FabricDatabase& fabrics);
/// Same for scene text held in memory (`name` appears in errors).
LoadedScene ParseScene(const std::string& text, const std::string& name, const FabricDatabase& fabrics);

}  // namespace haptex::scene
