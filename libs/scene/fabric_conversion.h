#pragma once
// haptex.v1.Fabric (scene files, the database) -> the physics core's plain mirror of it.

#include <string>

#include "haptex/v1/fabric.pb.h"
#include "libs/scene/fabric_database.h"
#include "libs/textile/kes_fabric.h"

namespace haptex::scene {

/// Field-for-field copy, same units (KES). Validation is the core's and ValidateFabric's job.
textile::kes::Fabric ToKesFabric(const v1::Fabric& fabric);

/// Database fabric `name`, loaded and validated (FabricDatabase::Load, which throws
/// TextProtoError), as the core's mirror.
textile::kes::Fabric LoadKesFabric(const FabricDatabase& database, const std::string& name);
/// The same from FabricDatabase::DefaultDirectory().
textile::kes::Fabric LoadKesFabric(const std::string& name);

}  // namespace haptex::scene
