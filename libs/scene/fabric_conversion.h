#pragma once
// haptex.v1.Fabric (scene files, the database) -> the physics core's plain mirror of it.

#include "haptex/v1/fabric.pb.h"
#include "libs/textile/kes_fabric.h"

namespace haptex::scene {

/// Field-for-field copy, same units (KES). Validation is the core's and ValidateFabric's job.
textile::kes::Fabric ToKesFabric(const v1::Fabric& fabric);

}  // namespace haptex::scene
