#include "tests/textile/fabric_textproto.h"

#include "haptex/v1/fabric.pb.h"
#include "libs/scene/fabric_conversion.h"
#include "libs/scene/fabric_database.h"
#include "libs/scene/text_proto.h"
#include "tests/support/test_paths.h"

namespace haptex::textile::testing {

kes::Fabric ParseFabricTextproto(const std::string& text) {
  v1::Fabric fabric;
  scene::ParseTextProto(text, "fabric", &fabric);
  return scene::ToKesFabric(fabric);
}

kes::Fabric LoadDatabaseFabric(const std::string& name) {
  return scene::LoadKesFabric(scene::FabricDatabase(SourceDir() + "/data/fabrics"), name);
}

std::string SourceDir() { return haptex::testing::SourceDir(); }

}  // namespace haptex::textile::testing
