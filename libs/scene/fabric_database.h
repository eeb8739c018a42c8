#pragma once
// The fabric database: data/fabrics/NAME.textproto, one haptex.v1.Fabric per file.

#include <string>
#include <vector>

#include "haptex/v1/fabric.pb.h"
#include "libs/scene/text_proto.h"

namespace haptex::scene {

/// Checks the values a simulation needs (finite, positive, plausible) and reports each problem at
/// its field. Empty when the fabric is usable.
std::vector<TextIssue> ValidateFabric(const v1::Fabric& fabric, const FieldLocator& where);

class FabricDatabase {
 public:
  /// Throws std::runtime_error when the directory does not exist.
  explicit FabricDatabase(std::string directory);

  /// $HAPTEX_DATA_DIR/fabrics when set, else the source tree's data/fabrics.
  static std::string DefaultDirectory();

  /// Sorted database names (file names without .textproto).
  std::vector<std::string> Names() const;
  bool Contains(const std::string& name) const;
  /// Loads and validates one fabric. Throws TextProtoError (file:line:column) when the file is
  /// bad, when its name field differs from the file name, or when a value is unusable.
  v1::Fabric Load(const std::string& name) const;
  std::string PathOf(const std::string& name) const;
  const std::string& directory() const { return directory_; }

 private:
  std::string directory_;
};

}  // namespace haptex::scene
