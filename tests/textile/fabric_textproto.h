#pragma once
// The textile tests read the real fabric database through the production loader (libs/scene),
// so they test the same data path the services use.

#include <string>

#include "libs/textile/kes_fabric.h"

namespace haptex::textile::testing {

/// Parses one haptex.v1.Fabric text-format text. Throws scene::TextProtoError on errors.
kes::Fabric ParseFabricTextproto(const std::string& text);
/// Loads and validates data/fabrics/<name>.textproto from the source tree.
kes::Fabric LoadDatabaseFabric(const std::string& name);
/// The source tree (HAPTEX_SOURCE_DIR, else the configured one).
std::string SourceDir();

}  // namespace haptex::textile::testing
