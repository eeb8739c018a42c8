#include "libs/scene/fabric_conversion.h"

namespace haptex::scene {
namespace {

textile::kes::Source ToSource(const v1::Source& s) { return {s.citation(), s.locator(), s.note()}; }

textile::kes::KesTensile ToTensile(const v1::KesTensile& t) {
  textile::kes::KesTensile out;
  out.emt_percent = t.emt_percent();
  out.lt = t.lt();
  out.wt_gfcm_per_cm2 = t.wt_gfcm_per_cm2();
  out.rt_percent = t.rt_percent();
  out.fm_gf_per_cm = t.fm_gf_per_cm();
  for (const auto& p : t.loading_curve()) out.loading_curve.push_back({p.x(), p.y()});
  return out;
}

textile::kes::KesBending ToBending(const v1::KesBending& b) { return {b.b_gfcm2_per_cm(), b.two_hb_gfcm_per_cm()}; }

}  // namespace

textile::kes::Fabric ToKesFabric(const v1::Fabric& f) {
  textile::kes::Fabric out;
  out.name = f.name();
  out.description = f.description();
  out.source = ToSource(f.source());
  out.direction_known = f.direction_known();
  out.warp_tensile = ToTensile(f.warp_tensile());
  out.weft_tensile = ToTensile(f.weft_tensile());
  out.shear = {f.shear().g_gf_per_cm_deg(), f.shear().two_hg_gf_per_cm(), f.shear().two_hg5_gf_per_cm()};
  out.warp_bending = ToBending(f.warp_bending());
  out.weft_bending = ToBending(f.weft_bending());
  out.compression = {f.compression().lc(), f.compression().wc_gfcm_per_cm2(), f.compression().rc_percent()};
  out.surface = {f.surface().miu(), f.surface().mmd(), f.surface().smd_um()};
  out.thickness_mm = f.thickness_mm();
  out.weight_mg_per_cm2 = f.weight_mg_per_cm2();
  out.finger_friction = {f.finger_friction().mu_static(), f.finger_friction().mu_dynamic(),
                         ToSource(f.finger_friction().source())};
  out.weave.pattern = static_cast<textile::kes::Weave::Pattern>(f.weave().pattern());
  out.weave.warp_pitch_mm = f.weave().warp_pitch_mm();
  out.weave.weft_pitch_mm = f.weave().weft_pitch_mm();
  out.weave.yarn_diameter_mm = f.weave().yarn_diameter_mm();
  for (const auto& flag : f.flags()) {
    out.flags.push_back({flag.field(), flag.as_printed(), flag.problem(), flag.resolution()});
  }
  for (const auto& s : f.other_sources()) out.other_sources.push_back(ToSource(s));
  return out;
}

textile::kes::Fabric LoadKesFabric(const FabricDatabase& database, const std::string& name) {
  return ToKesFabric(database.Load(name));
}

textile::kes::Fabric LoadKesFabric(const std::string& name) {
  return LoadKesFabric(FabricDatabase(FabricDatabase::DefaultDirectory()), name);
}

}  // namespace haptex::scene
