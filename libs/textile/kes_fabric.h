#pragma once
// Plain C++ mirror of the protobuf message haptex.v1.Fabric (proto/haptex/v1/fabric.proto), in
// the same KES units. Field names are identical to the proto's, so the proto -> struct copy
// (libs/scene) is trivial and this core stays free of protobuf.

#include <string>
#include <vector>

namespace haptex::textile::kes {

/// Where a number comes from.
struct Source {
  std::string citation;  ///< authors, title, venue, year
  std::string locator;   ///< table/figure/page, DOI or URL
  std::string note;      ///< e.g. how a derived value was computed
};

/// A value that a source prints wrongly, and what is used instead.
struct DataFlag {
  std::string field;
  std::string as_printed;
  std::string problem;
  std::string resolution;
};

/// One point of a digitized loading curve: x strain [-] (tensile), y force per width [gf/cm].
struct CurvePoint {
  double x = 0.0;
  double y = 0.0;
};

/// KES-FB1 tensile block for one direction.
struct KesTensile {
  double emt_percent = 0.0;               ///< EMT: strain at Fm [%]
  double lt = 0.0;                        ///< LT: linearity [-]
  double wt_gfcm_per_cm2 = 0.0;           ///< WT: tensile energy [gf cm / cm^2]
  double rt_percent = 0.0;                ///< RT: resilience [%]
  double fm_gf_per_cm = 0.0;              ///< maximum load of the test [gf/cm]; 0 means 500
  std::vector<CurvePoint> loading_curve;  ///< digitized loading curve, if the source gives one
};

/// KES-FB1 shear block.
struct KesShear {
  double g_gf_per_cm_deg = 0.0;    ///< G [gf / (cm deg)]
  double two_hg_gf_per_cm = 0.0;   ///< 2HG at 0.5 deg [gf/cm]
  double two_hg5_gf_per_cm = 0.0;  ///< 2HG5 at 5 deg [gf/cm]
};

/// KES-FB2 bending block for one direction.
struct KesBending {
  double b_gfcm2_per_cm = 0.0;      ///< B [gf cm^2 / cm]
  double two_hb_gfcm_per_cm = 0.0;  ///< 2HB [gf cm / cm]
};

/// KES-FB3 compression block.
struct KesCompression {
  double lc = 0.0;
  double wc_gfcm_per_cm2 = 0.0;
  double rc_percent = 0.0;
};

/// KES-FB4 surface block.
struct KesSurface {
  double miu = 0.0;
  double mmd = 0.0;
  double smd_um = 0.0;
};

/// Fingertip friction on this fabric (not a KES value).
struct FingerFriction {
  double mu_static = 0.0;
  double mu_dynamic = 0.0;
  Source source;
};

/// Woven structure.
struct Weave {
  enum class Pattern { kUnspecified = 0, kPlain = 1, kTwill = 2, kSatin = 3, kKnit = 4 };
  Pattern pattern = Pattern::kUnspecified;
  double warp_pitch_mm = 0.0;
  double weft_pitch_mm = 0.0;
  double yarn_diameter_mm = 0.0;
};

/// Mirror of haptex.v1.Fabric.
struct Fabric {
  std::string name;
  std::string description;
  Source source;
  bool direction_known = false;
  KesTensile warp_tensile;
  KesTensile weft_tensile;
  KesShear shear;
  KesBending warp_bending;
  KesBending weft_bending;
  KesCompression compression;
  KesSurface surface;
  double thickness_mm = 0.0;       ///< T at 0.5 gf/cm^2 [mm]
  double weight_mg_per_cm2 = 0.0;  ///< W [mg/cm^2]
  FingerFriction finger_friction;
  Weave weave;
  std::vector<DataFlag> flags;
  std::vector<Source> other_sources;
};

}  // namespace haptex::textile::kes
