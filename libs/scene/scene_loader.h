#pragma once
// Loading a scene: parse, resolve its fabric, validate every field. Any problem refuses the whole
// scene with file:line:column and what is wrong.

#include <cstddef>
#include <cstdint>
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

/// A scene's name names its run folder and appears in every report: one line, at most this long.
inline constexpr std::size_t kMaxSceneNameBytes = 100;
/// Host names end up in run folders and service identities ("launcher@NAME").
inline constexpr std::size_t kMaxHostNameBytes = 64;
/// Positions a scene gives in W (the stand, the mock user's touch point, the device) lie within
/// this of W's origin: the fabric and the device share a table, not a building.
inline constexpr double kMaxWorldDistanceM = 10.0;
/// How far from 1 the norm of a rotation a scene gives may be (it is then normalised): four
/// decimals per component are enough.
inline constexpr double kQuaternionNormTolerance = 1e-3;
/// The particle steps per second the global loop can take (particles x global rate): the fabric
/// step costs about 2.6-3.2 us per particle on one core (41 x 41 in 3.8-4.3 ms, 81 x 81 in about
/// 21 ms; docs/validation.md section 6), so 200 000 use at most 0.65 of a core and leave room for a
/// loaded host. 41 x 41 runs at up to 118 Hz, 81 x 81 at up to 30 Hz.
inline constexpr double kMaxParticleStepsPerSecond = 200000.0;

/// Semantic checks of a parsed scene (fabric data included). Empty when usable.
std::vector<TextIssue> ValidateScene(const v1::Scene& scene, const FieldLocator& where, const FabricDatabase& fabrics);

/// Throws TextProtoError listing every problem.
LoadedScene LoadScene(const std::string& path, const FabricDatabase& fabrics);
/// Same for scene text held in memory (`name` appears in errors).
LoadedScene ParseScene(const std::string& text, const std::string& name, const FabricDatabase& fabrics);

}  // namespace haptex::scene
