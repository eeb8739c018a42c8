#include "libs/scene/scene_loader.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <sstream>

#include "libs/device/grab_protocol.h"
#include "libs/device/trajectory_csv.h"
#include "libs/net/session_key.h"
#include "libs/net/udp_address.h"
#include "libs/scene/field_checks.h"
#include "libs/scene/scene_defaults.h"
#include "libs/scene/scene_network.h"
#include "libs/scene/scene_stalls.h"
#include "libs/textile/step_options.h"

namespace haptex::scene {
namespace {

using google::protobuf::Message;

// Collects issues while walking the scene.
class Checker {
 public:
  explicit Checker(std::vector<TextIssue>* issues) : issues_(issues) {}

  // value == 0 means "default"; otherwise it must lie in [min, max].
  void ZeroOrRange(const Message& m, const char* field, double value, double min, double max, const char* unit,
                   const FieldLocator& at) {
    if (value == 0.0) return;
    Range(m, field, value, min, max, unit, at);
  }
  void Range(const Message& m, const char* field, double value, double min, double max, const char* unit,
             const FieldLocator& at) {
    if (!std::isfinite(value)) return;  // CheckEveryField reports what is not a number
    if (value < min || value > max) {
      Add(at.At(m, field, -1,
                std::string(field) + " must be in [" + Number(min) + ", " + Number(max) + "] " + unit + ", got " +
                    Number(value)));
    }
  }
  void Add(TextIssue issue) { issues_->push_back(std::move(issue)); }

  static std::string Number(double v) {
    std::ostringstream out;
    out << v;
    return out.str();
  }

 private:
  std::vector<TextIssue>* issues_;
};

void CheckVec(const Message& parent, const char* field, const v1::Vec3& v, double max_norm, const char* unit,
              const FieldLocator& at, Checker& c) {
  // a component that is not a number is CheckEveryField's to report, at the component
  if (!std::isfinite(v.x()) || !std::isfinite(v.y()) || !std::isfinite(v.z())) return;
  const double norm = std::sqrt(v.x() * v.x() + v.y() * v.y() + v.z() * v.z());
  if (!std::isfinite(norm) || norm > max_norm) {
    c.Add(at.At(parent, field, -1,
                std::string(field) + " must have a magnitude <= " + Checker::Number(max_norm) + " " + unit + ", got " +
                    Checker::Number(norm)));
  }
}

void CheckCloth(const v1::ClothGeometry& cloth, const FieldLocator& at, Checker& c) {
  c.ZeroOrRange(cloth, "width_m", cloth.width_m(), 0.01, 5.0, "m", at);
  c.ZeroOrRange(cloth, "height_m", cloth.height_m(), 0.01, 5.0, "m", at);
  c.ZeroOrRange(cloth, "particles_u", cloth.particles_u(), 2, 401, "particles", at);
  c.ZeroOrRange(cloth, "particles_v", cloth.particles_v(), 2, 401, "particles", at);
  // One turn either way covers every cut; a larger value is more likely a unit slip (radians
  // written as degrees cannot be caught, larger numbers can).
  c.Range(cloth, "material_angle_deg", cloth.material_angle_deg(), -kMaxMaterialAngleDeg, kMaxMaterialAngleDeg, "deg",
          at);
  const double height = ClothHeightM(cloth);
  if (cloth.mounting() == v1::ClothGeometry::MOUNTING_FLAT_LEDGE) {
    c.Range(cloth, "ledge_v_m", cloth.ledge_v_m(), 1e-3, height, "m (must lie on the cloth)", at);
  }
  const auto count =
      static_cast<std::uint64_t>(ClothParticlesU(cloth)) * static_cast<std::uint64_t>(ClothParticlesV(cloth));
  CheckVec(cloth, "stand_position_w_m", cloth.stand_position_w_m(), kMaxWorldDistanceM, "m from W's origin", at, c);
  for (int i = 0; i < cloth.fixed_particles_size(); ++i) {
    if (cloth.fixed_particles(i) >= count) {
      c.Add(at.At(cloth, "fixed_particles", i,
                  "fixed particle " + std::to_string(cloth.fixed_particles(i)) + " does not exist (the grid has " +
                      std::to_string(count) + " particles)"));
    }
  }
}

void CheckLoads(const v1::Scene& scene, const FieldLocator& where, Checker& c) {
  const auto particles = static_cast<std::uint64_t>(ClothParticlesU(scene.cloth())) *
                         static_cast<std::uint64_t>(ClothParticlesV(scene.cloth()));
  for (int i = 0; i < scene.loads_size(); ++i) {
    const v1::Load& load = scene.loads(i);
    const FieldLocator at = where.Nested(scene, "loads", i);
    if (load.kind() == v1::Load::KIND_POINT && load.particle() >= particles) {
      c.Add(at.At(load, "particle", -1,
                  "particle " + std::to_string(load.particle()) + " does not exist (the grid has " +
                      std::to_string(particles) + ")"));
    }
    if (load.kind() == v1::Load::KIND_UNSPECIFIED) {
      c.Add(at.Here("load needs a kind (KIND_POINT or KIND_BOTTOM_EDGE)"));
    }
    CheckVec(load, "force_w_n", load.force_w_n(), 100.0, "N", at, c);
    c.Range(load, "start_s", load.start_s(), 0.0, 1e6, "s", at);
    c.Range(load, "ramp_s", load.ramp_s(), 0.0, 1e3, "s", at);
    if (load.end_s() != 0.0 && !(load.end_s() > load.start_s())) {
      c.Add(at.At(load, "end_s", -1, "end_s must be after start_s (or 0: until the end)"));
    }
  }
}

void CheckFingers(const v1::Scene& scene, const FieldLocator& where, Checker& c) {
  std::set<int> seen;
  if (scene.fingers_size() > 2) {
    c.Add(where.At(scene, "fingers", 2, "at most two fingers (thumb and index)"));
  }
  for (int i = 0; i < scene.fingers_size(); ++i) {
    const v1::FingerSpec& finger = scene.fingers(i);
    const FieldLocator at = where.Nested(scene, "fingers", i);
    if (finger.finger() == v1::FINGER_UNSPECIFIED) {
      c.Add(at.Here("finger needs `finger: FINGER_THUMB` or `finger: FINGER_INDEX`"));
    } else if (!seen.insert(finger.finger()).second) {
      c.Add(at.At(finger, "finger", -1, "this finger is listed twice"));
    }
    c.ZeroOrRange(finger, "radius_m", finger.radius_m(), 0.002, 0.03, "m", at);
    c.Range(finger, "length_m", finger.length_m(), 0.0, 0.05, "m", at);
  }
}

void CheckFriction(const v1::FrictionSpec& f, const FieldLocator& at, Checker& c) {
  c.Range(f, "finger_fabric_mu_static", f.finger_fabric_mu_static(), 0.0, 3.0, "", at);
  c.Range(f, "finger_fabric_mu_dynamic", f.finger_fabric_mu_dynamic(), 0.0, 3.0, "", at);
  c.Range(f, "finger_finger_mu_static", f.finger_finger_mu_static(), 0.0, 3.0, "", at);
  c.Range(f, "finger_finger_mu_dynamic", f.finger_finger_mu_dynamic(), 0.0, 3.0, "", at);
  if (f.finger_fabric_mu_static() != 0 && f.finger_fabric_mu_dynamic() > f.finger_fabric_mu_static()) {
    c.Add(at.At(f, "finger_fabric_mu_dynamic", -1, "dynamic friction must not exceed static friction"));
  }
  if (f.finger_finger_mu_static() != 0 && f.finger_finger_mu_dynamic() > f.finger_finger_mu_static()) {
    c.Add(at.At(f, "finger_finger_mu_dynamic", -1, "dynamic friction must not exceed static friction"));
  }
}

// Pitches of 0.05-5 mm cover silk to coarse canvas; yarns thicker than their pitch cannot lie side by side.
void CheckTactileSurface(const v1::TactileSurface& s, const FieldLocator& at, Checker& c) {
  c.ZeroOrRange(s, "warp_pitch_mm", s.warp_pitch_mm(), 0.05, 5.0, "mm", at);
  c.ZeroOrRange(s, "weft_pitch_mm", s.weft_pitch_mm(), 0.05, 5.0, "mm", at);
  c.ZeroOrRange(s, "yarn_diameter_mm", s.yarn_diameter_mm(), 0.02, 5.0, "mm", at);
  c.ZeroOrRange(s, "smd_um", s.smd_um(), 0.1, 100.0, "um", at);
  if (s.pattern() == v1::Weave::PATTERN_KNIT) {
    c.Add(at.At(s, "pattern", -1,
                "the tactile surface is built for woven patterns: PATTERN_PLAIN, PATTERN_TWILL or PATTERN_SATIN"));
  }
  const bool any_value = s.pattern() != v1::Weave::PATTERN_UNSPECIFIED || s.warp_pitch_mm() != 0 ||
                         s.weft_pitch_mm() != 0 || s.yarn_diameter_mm() != 0 || s.smd_um() != 0;
  if (any_value && s.source().citation().empty()) {
    c.Add(at.Here("surface values need their origin: `source { citation: \"...\" locator: \"...\" note: \"...\" }`"));
  }
}

void CheckDevice(const v1::Scene& scene, const FieldLocator& where, Checker& c) {
  const v1::DeviceSpec& d = scene.device();
  const FieldLocator at = where.Nested(scene, "device");
  if (scene.fingers_size() > 0 && d.kind_case() == v1::DeviceSpec::KIND_NOT_SET) {
    c.Add(where.At(scene, "fingers", 0,
                   "a scene with fingers needs a device: `device { mock {} }` or `device { grab { controller_address: "
                   "\"host:port\" } }`"));
  }
  if (d.has_grab()) {
    try {
      net::ResolveUdpAddress(d.grab().controller_address());
    } catch (const std::exception& e) {
      c.Add(at.Nested(d, "grab").At(d.grab(), "controller_address", -1, e.what()));
    }
  }
  if (d.has_mock()) {
    const v1::MockUserScript& user = d.mock().user();
    const FieldLocator u = at.Nested(d, "mock").Nested(d.mock(), "user");
    c.ZeroOrRange(user, "speed_m_per_s", user.speed_m_per_s(), 1e-3, 1.0, "m/s", u);
    c.ZeroOrRange(user, "stretch_speed_m_per_s", user.stretch_speed_m_per_s(), 1e-4, 1.0, "m/s", u);
    c.ZeroOrRange(user, "squeeze_force_n", user.squeeze_force_n(), 0.05, 20.0, "N", u);
    c.Range(user, "stretch_m", user.stretch_m(), 0.0, 0.1, "m", u);
    c.Range(user, "rub_amplitude_m", user.rub_amplitude_m(), 0.0, 0.1, "m", u);
    c.Range(user, "hold_s", user.hold_s(), 0.0, 60.0, "s", u);
    c.ZeroOrRange(user, "fold_angle_deg", user.fold_angle_deg(), 1.0, 180.0, "deg", u);
    CheckVec(user, "touch_point_w_m", user.touch_point_w_m(), kMaxWorldDistanceM, "m from W's origin", u, c);
    if (user.kind() == v1::MockUserScript::KIND_PLAYBACK && user.playback_csv().empty()) {
      c.Add(u.At(user, "kind", -1, "KIND_PLAYBACK needs playback_csv"));
    }
  }
  c.ZeroOrRange(d, "peak_force_n", d.peak_force_n(), 0.1, 20.0, "N (the GRAB's peak)", at);
  c.ZeroOrRange(d, "continuous_force_n", d.continuous_force_n(), 0.1, 6.0, "N (the GRAB's continuous limit)", at);
  if (d.peak_force_n() != 0 && d.continuous_force_n() > d.peak_force_n()) {
    c.Add(at.At(d, "continuous_force_n", -1, "continuous force must not exceed peak force"));
  }
  c.ZeroOrRange(d, "force_model_stale_s", d.force_model_stale_s(), 1e-4, 0.02, "s", at);
  c.ZeroOrRange(d, "watchdog_ramp_s", d.watchdog_ramp_s(), 1e-4, 0.02, "s", at);
  c.ZeroOrRange(d, "controller_lost_s", d.controller_lost_s(), 1e-3, 1.0, "s", at);
  c.ZeroOrRange(d, "max_model_age_s", d.max_model_age_s(), 0.005, 0.5, "s (the longest round trip rendered)", at);
  CheckVec(d, "d_origin_w_m", d.d_origin_w_m(), kMaxWorldDistanceM, "m from W's origin", at, c);
  if (d.has_q_wd()) {
    const v1::Quat& q = d.q_wd();
    const double norm = std::sqrt(q.w() * q.w() + q.x() * q.x() + q.y() * q.y() + q.z() * q.z());
    // a component that is not a number is CheckEveryField's to report
    if (std::isfinite(norm) && !(std::abs(norm - 1.0) <= kQuaternionNormTolerance)) {
      c.Add(at.At(d, "q_wd", -1,
                  "q_wd must be a unit quaternion (w, x, y, z) with |q| within " +
                      Checker::Number(kQuaternionNormTolerance) + " of 1, got |q| = " + Checker::Number(norm)));
    }
  }
  if (d.bridge_controller_port() > 65535) {
    c.Add(at.At(d, "bridge_controller_port", -1,
                "bridge_controller_port must be 0 (the launcher picks) or 1..65535, got " +
                    std::to_string(d.bridge_controller_port())));
  }
}

// A LocalPatch travels in one datagram (no fragmentation): the largest patch the fingers can cause,
// refined, must fit. Its side: the finger's reach plus the margin on both sides, one border ring
// each way and one cell for the even corner; about 90 bytes per particle (id, rest uv, position,
// velocity, mass, border flag, two triangles).
void CheckPatchFitsADatagram(const v1::Scene& scene, const FieldLocator& mo, Checker& c) {
  const v1::ModelOptions& m = scene.model();
  if (scene.fingers_size() == 0 || m.patch_refinement() > 4) return;
  const double radius_m = FingerReachM(scene) + PatchMarginM(scene);
  const v1::ClothGeometry& cloth = scene.cloth();
  const int nu = ClothParticlesU(cloth), nv = ClothParticlesV(cloth);
  if (nu < 2 || nv < 2) return;  // refused by the cloth checks
  const int factor = 1 << m.patch_refinement();
  auto side = [&](double spacing_m, int particles) {
    const double coarse = std::min<double>(particles, std::floor(2 * radius_m / spacing_m) + 1 + 2 + 1);
    return (coarse - 1) * factor + 1;
  };
  const double particles = side(ClothWidthM(cloth) / (nu - 1), nu) * side(ClothHeightM(cloth) / (nv - 1), nv);
  constexpr double kBytesPerParticle = 90.0;
  constexpr double kDatagramBytes = 60000.0;
  if (particles * kBytesPerParticle > kDatagramBytes) {
    c.Add(mo.At(m, "patch_refinement", -1,
                "patches could reach " + std::to_string(static_cast<long>(particles)) + " particles (about " +
                    std::to_string(static_cast<long>(particles * kBytesPerParticle / 1000)) +
                    " kB), over one 60 kB datagram: lower patch_refinement or patch_radius_m, or use a coarser cloth"));
  }
}

void CheckRatesAndModel(const v1::Scene& scene, const FieldLocator& where, Checker& c) {
  const v1::Rates& r = scene.rates();
  const FieldLocator at = where.Nested(scene, "rates");
  c.ZeroOrRange(r, "global_hz", r.global_hz(), 1, 1000, "Hz", at);
  c.ZeroOrRange(r, "local_hz", r.local_hz(), 100, 10000, "Hz", at);
  c.ZeroOrRange(r, "bridge_hz", r.bridge_hz(), device::kMinGrabRate_Hz, device::kMaxGrabRate_Hz,
                "Hz (docs/grab-protocol.md section 1)", at);
  c.ZeroOrRange(r, "finger_states_to_local_hz", r.finger_states_to_local_hz(), 10, 20000, "Hz", at);
  c.ZeroOrRange(r, "finger_states_to_global_hz", r.finger_states_to_global_hz(), 1, 1000, "Hz", at);
  c.ZeroOrRange(r, "cloth_frame_hz", r.cloth_frame_hz(), 1, 60, "Hz", at);
  c.ZeroOrRange(r, "health_hz", r.health_hz(), 0.5, 100, "Hz", at);

  const v1::ModelOptions& m = scene.model();
  const FieldLocator mo = where.Nested(scene, "model");
  c.ZeroOrRange(m, "global_dt_s", m.global_dt_s(), 1e-5, 0.1, "s", mo);
  c.ZeroOrRange(m, "cg_tolerance", m.cg_tolerance(), 1e-12, 0.5, "", mo);
  c.ZeroOrRange(m, "cg_max_iterations", m.cg_max_iterations(), 1, 100000, "", mo);
  c.ZeroOrRange(m, "local_cg_tolerance", m.local_cg_tolerance(), 1e-12, 0.5, "", mo);
  c.ZeroOrRange(m, "local_cg_max_iterations", m.local_cg_max_iterations(), 3, 100000, "", mo);
  c.ZeroOrRange(m, "substeps", m.substeps(), 1, 10000, "", mo);
  c.ZeroOrRange(m, "newton_max_iterations", m.newton_max_iterations(), 1, 100, "", mo);
  c.ZeroOrRange(m, "newton_tolerance", m.newton_tolerance(), 1e-12, 0.5, "", mo);
  if (m.global_integrator() == v1::ModelOptions::INTEGRATOR_BDF2 && m.newton_max_iterations() < 2) {
    c.Add(mo.At(m, "global_integrator", -1,
                "INTEGRATOR_BDF2 needs newton_max_iterations of 2 or more (one linearised step of it pumps energy "
                "into stiff or strongly nonlinear fabrics)"));
  }
  if (m.global_integrator() == v1::ModelOptions::INTEGRATOR_BDF2 &&
      SceneRunsService(scene, v1::ServicePlacement::SERVICE_LOCAL_CONTACT)) {
    c.Add(mo.At(m, "global_integrator", -1,
                "INTEGRATOR_BDF2 is for a cloth without local_contact: patch results merged a step late into its "
                "history made a pinch overshoot 2.4 times (docs/fabric-model.md, BDF2)"));
  }
  if (m.local_integrator() == v1::ModelOptions::INTEGRATOR_BDF2) {
    c.Add(mo.At(m, "local_integrator", -1,
                "INTEGRATOR_BDF2 is for the global layer: the haptic patch takes one linearised step each tick, "
                "too few for BDF2"));
  }
  c.Range(m, "max_step_halvings", m.max_step_halvings(), 0, textile::kMaxStepHalvings, "", mo);
  c.Range(m, "max_strain_rise_per_step", m.max_strain_rise_per_step(), 0.0, 1.0, "", mo);
  c.Range(m, "patch_radius_m", m.patch_radius_m(), 0.0, 0.1, "m", mo);
  c.Range(m, "patch_refinement", m.patch_refinement(), 0, 4, "", mo);
  CheckPatchFitsADatagram(scene, mo, c);
  c.Range(m, "air_drag_linear", m.air_drag_linear(), 0.0, 100.0, "", mo);
  c.Range(m, "air_drag_quadratic", m.air_drag_quadratic(), 0.0, 10.0, "", mo);
}

void CheckPlacement(const v1::Scene& scene, const FieldLocator& where, Checker& c) {
  std::set<std::string> hosts = {"local"};
  for (int i = 0; i < scene.hosts_size(); ++i) {
    const v1::Host& host = scene.hosts(i);
    const FieldLocator at = where.Nested(scene, "hosts", i);
    if (host.name().empty()) c.Add(at.Here("host needs a name"));
    if (host.address().empty()) c.Add(at.At(host, "name", -1, "host '" + host.name() + "' needs an address"));
    if (host.name() != "local" && !hosts.insert(host.name()).second) {
      c.Add(at.At(host, "name", -1, "host '" + host.name() + "' is defined twice"));
    }
  }
  std::set<int> services;
  std::set<std::pair<std::string, std::uint32_t>> ports;
  for (int i = 0; i < scene.services_size(); ++i) {
    const v1::ServicePlacement& s = scene.services(i);
    const FieldLocator at = where.Nested(scene, "services", i);
    if (s.service() == v1::ServicePlacement::SERVICE_UNSPECIFIED) c.Add(at.Here("placement needs a service"));
    if (!services.insert(s.service()).second) c.Add(at.At(s, "service", -1, "service placed twice"));
    const std::string host = s.host().empty() ? "local" : s.host();
    if (!hosts.count(host)) c.Add(at.At(s, "host", -1, "unknown host '" + host + "' (define it under hosts)"));
    if (s.port() > 65535) c.Add(at.At(s, "port", -1, "port must be 0..65535"));
    if (s.port() != 0 && !ports.insert({host, s.port()}).second) {
      c.Add(at.At(s, "port", -1, "port " + std::to_string(s.port()) + " is used twice on host " + host));
    }
  }
}

void CheckSessionKey(const v1::Scene& scene, const FieldLocator& where, Checker& c) {
  const v1::SessionKey& key = scene.session_key();
  const FieldLocator at = where.Nested(scene, "session_key");
  switch (key.source_case()) {
    case v1::SessionKey::kHex:
      try {
        net::SessionKey::FromHex(key.hex());
      } catch (const std::exception& e) {
        c.Add(at.At(key, "hex", -1, e.what()));
      }
      break;
    case v1::SessionKey::kEnv:
      if (key.env().empty()) c.Add(at.At(key, "env", -1, "env needs a variable name"));
      break;
    case v1::SessionKey::kFile:
      if (key.file().empty()) c.Add(at.At(key, "file", -1, "file needs a path"));
      break;
    default:
      break;
  }
}

// Strings that become file names, identities or paths: the generic checks bound every string;
// these are the rules of what each one names.
void CheckSceneName(const v1::Scene& scene, const FieldLocator& where, Checker& c) {
  const std::string& name = scene.name();
  if (name.empty()) {
    c.Add(where.Here("scene needs a name"));
  } else if (IsWellFormedText(name) && name.find_first_of("\n\t") != std::string::npos) {
    c.Add(where.At(scene, "name", -1, "name must be one line without tabs (it names the run folder)"));
  }
}

void CheckNamesAndPaths(const v1::Scene& scene, const FieldLocator& where, Checker& c) {
  if (scene.fabric().has_database_name() && IsWellFormedText(scene.fabric().database_name()) &&
      !IsPlainName(scene.fabric().database_name(), kMaxStringBytes)) {
    c.Add(where.Nested(scene, "fabric")
              .At(scene.fabric(), "database_name", -1,
                  "database_name must be a file name in the database (letters, digits, '_', '-', '.'; not a path)"));
  }
  for (int i = 0; i < scene.hosts_size(); ++i) {
    const v1::Host& host = scene.hosts(i);
    const FieldLocator at = where.Nested(scene, "hosts", i);
    if (!host.name().empty() && IsWellFormedText(host.name()) && !IsPlainName(host.name(), kMaxStringBytes)) {
      c.Add(at.At(host, "name", -1, "host name must be letters, digits, '_', '-' or '.' (not starting with '.')"));
    }
    if (IsWellFormedText(host.address()) && host.address().find_first_of(" \t\n") != std::string::npos) {
      c.Add(at.At(host, "address", -1, "address must be an IP literal or a host name (no spaces)"));
    }
  }
  const v1::SessionKey& key = scene.session_key();
  if (key.has_env() && !key.env().empty() && IsWellFormedText(key.env())) {
    const std::string& env = key.env();
    const bool valid = (std::isalpha(static_cast<unsigned char>(env[0])) || env[0] == '_') &&
                       std::all_of(env.begin(), env.end(),
                                   [](char ch) { return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_'; });
    if (!valid) {
      c.Add(where.Nested(scene, "session_key")
                .At(key, "env", -1, "env must name an environment variable (letters, digits and '_')"));
    }
  }
  const v1::MockUserScript& user = scene.device().mock().user();
  if (scene.device().has_mock() && user.kind() == v1::MockUserScript::KIND_PLAYBACK && !user.playback_csv().empty()) {
    std::error_code error;
    const bool regular = std::filesystem::is_regular_file(user.playback_csv(), error);
    const std::uintmax_t bytes = regular ? std::filesystem::file_size(user.playback_csv(), error) : 0;
    if (!regular || error || bytes > device::kMaxTrajectoryCsvBytes) {
      const FieldLocator u =
          where.Nested(scene, "device").Nested(scene.device(), "mock").Nested(scene.device().mock(), "user");
      c.Add(u.At(user, "playback_csv", -1,
                 "playback_csv must be a readable file of at most " +
                     std::to_string(device::kMaxTrajectoryCsvBytes >> 20) + " MB (not a device or folder)"));
    }
  }
}

// The global loop steps the whole cloth once per period: more particles than it can step at the
// scene's rate would run slower than real time (a 401 x 401 cloth ran at about 1 Hz).
void CheckGlobalLoopBudget(const v1::Scene& scene, const FieldLocator& where, Checker& c) {
  const v1::ClothGeometry& cloth = scene.cloth();
  const double nu = ClothParticlesU(cloth), nv = ClothParticlesV(cloth);
  const double rate_hz = GlobalRateHz(scene);
  if (!std::isfinite(rate_hz) || nu * nv * rate_hz <= kMaxParticleStepsPerSecond) return;
  const auto whole = [](double x) { return std::to_string(static_cast<long long>(std::floor(x))); };
  const double max_rate_hz = kMaxParticleStepsPerSecond / (nu * nv);
  const double max_side = std::sqrt(kMaxParticleStepsPerSecond / rate_hz);
  const FieldLocator at = where.Nested(scene, "cloth");
  const char* field = cloth.particles_u() != 0 ? "particles_u" : "particles_v";
  c.Add(at.At(cloth, field, -1,
              "a " + whole(nu) + " x " + whole(nv) + " cloth at " + Checker::Number(rate_hz) + " Hz needs " +
                  whole(nu * nv * rate_hz) + " particle steps per second, over the " +
                  whole(kMaxParticleStepsPerSecond) + " the global loop can take (docs/scenes.md): use at most " +
                  whole(max_side) + " x " + whole(max_side) + " particles at this rate" +
                  (max_rate_hz >= 1 ? ", or lower rates.global_hz to at most " + whole(max_rate_hz) + " Hz" : "")));
}

}  // namespace

std::vector<TextIssue> ValidateScene(const v1::Scene& scene, const FieldLocator& where, const FabricDatabase& fabrics) {
  std::vector<TextIssue> issues;
  {
    // numbers, enums and strings by their kind; an inline fabric is ValidateFabric's
    v1::Scene without_fabric = scene;
    without_fabric.mutable_fabric()->clear_inline_fabric();
    CheckEveryField(without_fabric, where, &issues,
                    {{"haptex.v1.Scene.name", kMaxSceneNameBytes},
                     {"haptex.v1.FabricChoice.database_name", kMaxSceneNameBytes},
                     {"haptex.v1.Host.name", kMaxHostNameBytes},
                     {"haptex.v1.Host.address", 253}});  // a DNS name's limit
  }
  Checker c(&issues);
  CheckSceneName(scene, where, c);
  CheckNamesAndPaths(scene, where, c);
  c.Range(scene, "duration_s", scene.duration_s(), 0.0, 7 * 24 * 3600.0, "s", where);

  const FieldLocator fabric_at = where.Nested(scene, "fabric");
  switch (scene.fabric().choice_case()) {
    case v1::FabricChoice::kDatabaseName:
      if (IsPlainName(scene.fabric().database_name(), kMaxSceneNameBytes) &&
          !fabrics.Contains(scene.fabric().database_name())) {
        std::string known;
        for (const auto& n : fabrics.Names()) known += (known.empty() ? "" : ", ") + n;
        c.Add(fabric_at.At(scene.fabric(), "database_name", -1,
                           "no fabric '" + scene.fabric().database_name() + "' in " + fabrics.directory() +
                               " (known: " + known + ")"));
      }
      break;
    case v1::FabricChoice::kInlineFabric:
      for (TextIssue& issue :
           ValidateFabric(scene.fabric().inline_fabric(), fabric_at.Nested(scene.fabric(), "inline_fabric"))) {
        c.Add(std::move(issue));
      }
      break;
    default:
      c.Add(where.Here(
          "scene needs a fabric: `fabric { database_name: \"...\" }` or `fabric { inline_fabric { ... } }`"));
  }
  CheckCloth(scene.cloth(), where.Nested(scene, "cloth"), c);
  CheckLoads(scene, where, c);
  CheckFingers(scene, where, c);
  CheckFriction(scene.friction(), where.Nested(scene, "friction"), c);
  CheckDevice(scene, where, c);
  if (scene.tactile().enabled()) {
    const FieldLocator at = where.Nested(scene, "tactile");
    if (scene.fingers_size() == 0) c.Add(at.At(scene.tactile(), "enabled", -1, "tactile display needs fingers"));
    c.ZeroOrRange(scene.tactile(), "display_rate_hz", scene.tactile().display_rate_hz(), 10, 5000, "Hz", at);
    CheckTactileSurface(scene.tactile().surface(), at.Nested(scene.tactile(), "surface"), c);
    if (!scene.tactile().mock_display()) {
      try {
        net::ResolveUdpAddress(scene.tactile().display_address());
      } catch (const std::exception& e) {
        c.Add(at.At(scene.tactile(), "display_address", -1,
                    std::string("a real display needs display_address (or mock_display: true): ") + e.what()));
      }
    }
  }
  if (scene.has_viewer()) {
    const FieldLocator at = where.Nested(scene, "viewer");
    if (scene.viewer().port() > 65535) c.Add(at.At(scene.viewer(), "port", -1, "port must be 0..65535"));
    if (!scene.viewer().bind_address().empty()) {
      try {
        net::ResolveUdpAddress(scene.viewer().bind_address() + ":0");
      } catch (const std::exception& e) {
        c.Add(at.At(scene.viewer(), "bind_address", -1,
                    std::string("viewer bind_address is not an address: ") + e.what()));
      }
    }
  }
  CheckRatesAndModel(scene, where, c);
  CheckPlacement(scene, where, c);
  CheckSessionKey(scene, where, c);
  // one issue per field: a number CheckEveryField refused is not reported again by the network's checks
  for (TextIssue& issue : ValidateNetwork(scene, where)) {
    const bool reported = std::any_of(issues.begin(), issues.end(), [&](const TextIssue& i) {
      return i.line == issue.line && i.column == issue.column;
    });
    if (!reported) c.Add(std::move(issue));
  }
  // likewise for the stalls, whose own issues may share a place (a stall that leaves out two fields)
  const std::size_t before_stalls = issues.size();
  for (TextIssue& issue : ValidateStalls(scene, where)) {
    const auto end = issues.begin() + static_cast<std::ptrdiff_t>(before_stalls);
    const bool reported = std::any_of(
        issues.begin(), end, [&](const TextIssue& i) { return i.line == issue.line && i.column == issue.column; });
    if (!reported) c.Add(std::move(issue));
  }
  CheckGlobalLoopBudget(scene, where, c);
  SortByLocation(&issues);
  return issues;
}

LoadedScene ParseScene(const std::string& text, const std::string& name, const FabricDatabase& fabrics) {
  LoadedScene loaded;
  loaded.path = name;
  const ParsedText parsed = ParseTextProto(text, name, &loaded.scene);
  const FieldLocator where(parsed.locations.get(), {1, 1, ""});
  std::vector<TextIssue> issues = ValidateScene(loaded.scene, where, fabrics);
  if (!issues.empty()) throw TextProtoError(name, std::move(issues));
  if (loaded.scene.fabric().has_inline_fabric()) {
    loaded.fabric = loaded.scene.fabric().inline_fabric();
  } else {
    loaded.fabric = fabrics.Load(loaded.scene.fabric().database_name());
  }
  return loaded;
}

LoadedScene LoadScene(const std::string& path, const FabricDatabase& fabrics) {
  return ParseScene(ReadTextFile(path), path, fabrics);
}

}  // namespace haptex::scene
