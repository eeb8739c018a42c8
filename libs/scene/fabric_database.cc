#include "libs/scene/fabric_database.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "libs/scene/field_checks.h"

#ifndef HAPTEX_DEFAULT_DATA_DIR
#error "HAPTEX_DEFAULT_DATA_DIR must be defined by the build"
#endif

namespace haptex::scene {
namespace {

constexpr char kExtension[] = ".textproto";

void RequireRange(const google::protobuf::Message& parent, const char* field, double value, double min_exclusive,
                  double max_inclusive, const char* unit, const FieldLocator& where, std::vector<TextIssue>* issues) {
  if (std::isfinite(value) && (value <= min_exclusive || value > max_inclusive)) {
    issues->push_back(where.At(parent, field, -1,
                               std::string(field) + " must be in (" + std::to_string(min_exclusive) + ", " +
                                   std::to_string(max_inclusive) + "] " + unit + ", got " + std::to_string(value)));
  }
}

}  // namespace

std::vector<TextIssue> ValidateFabric(const v1::Fabric& fabric, const FieldLocator& where) {
  std::vector<TextIssue> issues;
  CheckEveryField(fabric, where, &issues);  // what is not a number is reported there, once
  if (fabric.name().empty()) issues.push_back(where.Here("fabric has no name"));
  const std::pair<const char*, const v1::KesTensile*> tensiles[] = {{"warp_tensile", &fabric.warp_tensile()},
                                                                    {"weft_tensile", &fabric.weft_tensile()}};
  for (const auto& [direction, tensile_ptr] : tensiles) {
    const v1::KesTensile& tensile = *tensile_ptr;
    const FieldLocator at = where.Nested(fabric, direction);
    if (tensile.loading_curve_size() == 0) {
      RequireRange(tensile, "emt_percent", tensile.emt_percent(), 0.0, 300.0, "%", at, &issues);
      RequireRange(tensile, "lt", tensile.lt(), 0.0, 3.0, "(-)", at, &issues);
    }
    if (tensile.fm_gf_per_cm() < 0.0) {
      issues.push_back(at.At(tensile, "fm_gf_per_cm", -1, "fm_gf_per_cm must be >= 0 (0: 500 gf/cm)"));
    }
    for (int i = 0; i < tensile.loading_curve_size(); ++i) {
      const auto& p = tensile.loading_curve(i);
      const bool increasing =
          i == 0 || (p.x() > tensile.loading_curve(i - 1).x() && p.y() >= tensile.loading_curve(i - 1).y());
      if (!std::isfinite(p.x()) || !std::isfinite(p.y())) continue;
      if (p.x() < 0 || p.y() < 0 || !increasing) {
        issues.push_back(
            at.At(tensile, "loading_curve", i, "loading_curve points must be finite, >= 0 and increasing"));
      }
    }
  }
  const FieldLocator shear = where.Nested(fabric, "shear");
  RequireRange(fabric.shear(), "g_gf_per_cm_deg", fabric.shear().g_gf_per_cm_deg(), 0.0, 100.0, "gf/(cm deg)", shear,
               &issues);
  const std::pair<const char*, const v1::KesBending*> bendings[] = {{"warp_bending", &fabric.warp_bending()},
                                                                    {"weft_bending", &fabric.weft_bending()}};
  for (const auto& [direction, bending_ptr] : bendings) {
    const v1::KesBending& bending = *bending_ptr;
    RequireRange(bending, "b_gfcm2_per_cm", bending.b_gfcm2_per_cm(), 0.0, 100.0, "gf cm^2/cm",
                 where.Nested(fabric, direction), &issues);
  }
  // thickness 0: the source does not give it (contact uses a default offset)
  if (fabric.thickness_mm() < 0.0 || fabric.thickness_mm() > 20.0) {
    issues.push_back(
        where.At(fabric, "thickness_mm", -1,
                 "thickness_mm must be in [0, 20] mm (0: not given), got " + std::to_string(fabric.thickness_mm())));
  }
  RequireRange(fabric, "weight_mg_per_cm2", fabric.weight_mg_per_cm2(), 0.0, 200.0, "mg/cm^2", where, &issues);
  if (fabric.has_finger_friction()) {
    const auto& f = fabric.finger_friction();
    const FieldLocator at = where.Nested(fabric, "finger_friction");
    RequireRange(f, "mu_static", f.mu_static(), 0.0, 3.0, "(-)", at, &issues);
    RequireRange(f, "mu_dynamic", f.mu_dynamic(), 0.0, 3.0, "(-)", at, &issues);
    if (f.mu_dynamic() > f.mu_static()) {
      issues.push_back(at.At(f, "mu_dynamic", -1, "mu_dynamic must not exceed mu_static"));
    }
  }
  return issues;
}

FabricDatabase::FabricDatabase(std::string directory) : directory_(std::move(directory)) {
  if (!std::filesystem::is_directory(directory_)) {
    throw std::runtime_error("fabric database '" + directory_ +
                             "' is not a directory (set HAPTEX_DATA_DIR to the folder holding fabrics/)");
  }
}

std::string FabricDatabase::DefaultDirectory() {
  if (const char* dir = std::getenv("HAPTEX_DATA_DIR"); dir != nullptr && *dir != '\0') {
    return std::string(dir) + "/fabrics";
  }
  return std::string(HAPTEX_DEFAULT_DATA_DIR) + "/fabrics";
}

std::vector<std::string> FabricDatabase::Names() const {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(directory_)) {
    if (entry.is_regular_file() && entry.path().extension() == kExtension) {
      names.push_back(entry.path().stem().string());
    }
  }
  std::sort(names.begin(), names.end());
  return names;
}

// A name is a file in the database folder, never a path out of it.
bool FabricDatabase::Contains(const std::string& name) const {
  return IsPlainName(name, kMaxStringBytes) && std::filesystem::is_regular_file(PathOf(name));
}

std::string FabricDatabase::PathOf(const std::string& name) const { return directory_ + "/" + name + kExtension; }

v1::Fabric FabricDatabase::Load(const std::string& name) const {
  const std::string path = PathOf(name);
  if (!Contains(name)) {
    std::string known;
    for (const auto& n : Names()) known += (known.empty() ? "" : ", ") + n;
    throw TextProtoError(path, {{1, 1, "no fabric '" + name + "' in the database (known: " + known + ")"}});
  }
  v1::Fabric fabric;
  const ParsedText parsed = ParseTextProtoFile(path, &fabric);
  const FieldLocator where(parsed.locations.get(), {1, 1, ""});
  std::vector<TextIssue> issues = ValidateFabric(fabric, where);
  if (fabric.name() != name) {
    issues.push_back(
        where.At(fabric, "name", -1, "name '" + fabric.name() + "' differs from the file name '" + name + "'"));
  }
  SortByLocation(&issues);
  if (!issues.empty()) throw TextProtoError(path, std::move(issues));
  return fabric;
}

}  // namespace haptex::scene
