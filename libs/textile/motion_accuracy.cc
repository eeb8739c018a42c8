#include "libs/textile/motion_accuracy.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "libs/textile/external_force.h"
#include "libs/textile/fabric_energy.h"
#include "libs/textile/fabric_strain.h"
#include "libs/textile/validation.h"

namespace haptex::textile::validation {
namespace {

constexpr double kSample_s = 1e-3;

// Minimum-jerk blend 0 -> 1 over [0, T].
double Blend(double t_s, double T_s) {
  if (T_s <= 0.0) return 1.0;
  const double s = std::clamp(t_s / T_s, 0.0, 1.0);
  return s * s * s * (10.0 - 15.0 * s + 6.0 * s * s);
}

// The loads and anchors of the step that ends at t_end.
void Drive(const Motion& m, double t_end_s, FabricState* s) {
  if (m.kind == MotionKind::kPush || m.kind == MotionKind::kPushWhole) {
    const bool pushing = t_end_s <= m.release_s + 1e-12;
    for (std::size_t i = 0; i < m.gripped.size(); ++i) {
      SetPointLoad(m.gripped[i], pushing ? Eigen::Vector3d(m.push_share[i] * m.push_W_N) : Eigen::Vector3d::Zero(), s);
    }
  } else if (m.kind == MotionKind::kPinch) {
    // both pads together, about local contact's anchors, spread over the gripped disc
    constexpr double kGrip_N_per_m = 1000.0;
    const Eigen::Vector3d offset = Blend(t_end_s, m.stretch_s) * m.stretch_W_m;
    for (int p : m.gripped) {
      s->anchor_stiffness_N_per_m[p] = kGrip_N_per_m / static_cast<double>(m.gripped.size());
      s->anchor_W_m.segment<3>(3 * p) = m.start.x(p) + offset;
    }
  }
}

}  // namespace

MotionKind MotionKindNamed(const std::string& name) {
  if (name == "swing") return MotionKind::kSwing;
  if (name == "push") return MotionKind::kPush;
  if (name == "push_whole") return MotionKind::kPushWhole;
  if (name == "pinch") return MotionKind::kPinch;
  throw std::invalid_argument("unknown motion '" + name + "' (swing, push, push_whole, pinch)");
}

const char* MotionKindName(MotionKind kind) {
  switch (kind) {
    case MotionKind::kSwing:
      return "swing";
    case MotionKind::kPush:
      return "push";
    case MotionKind::kPushWhole:
      return "push_whole";
    case MotionKind::kPinch:
      return "pinch";
  }
  return "unknown";
}

StepOptions ConvergedOptions(double dt_s) {
  StepOptions o;
  // second order: at the reference's 0.1 ms its own error is far below that of any step it judges
  // (implicit Euler's damping at 0.1 ms would be of the order of BDF2's error at a few ms)
  o.method = Integrator::kBdf2;
  o.dt_s = dt_s;
  o.cg_tolerance = 1e-8;
  o.cg_max_iterations = 2000;
  o.newton_max_iterations = 30;
  o.newton_tolerance = 1e-8;
  o.newton_update_jacobian = true;
  o.max_step_halvings = 0;
  o.max_strain_rise_per_step = 0.0;
  return o;
}

FabricState SettledHanging(const FabricModel& model) {
  Placement hanging;
  hanging.axis_u_W = Eigen::Vector3d(0, 0, -1);
  hanging.axis_v_W = Eigen::Vector3d(1, 0, 0);
  FabricState s = MakeRestState(model, hanging);
  for (int p : WarpRow(model, 0)) s.Fix(p);
  FabricStepper stepper(model, ConvergedOptions(1e-3));
  for (int i = 0; i < 500; ++i) stepper.Step(&s);
  s.v_W_m_per_s.setZero();
  s.time_s = 0.0;
  s.diagnostics = {};
  return s;
}

Motion MakeMotion(MotionKind kind, const FabricModel& model, const FabricState& settled) {
  Motion m;
  m.kind = kind;
  if (kind == MotionKind::kSwing) {
    Placement flat;  // warp horizontal, weft along y
    flat.axis_u_W = Eigen::Vector3d(1, 0, 0);
    flat.axis_v_W = Eigen::Vector3d(0, 1, 0);
    m.start = MakeRestState(model, flat);
    for (int p : WarpRow(model, 0)) m.start.Fix(p);
    m.duration_s = 1.0;
    m.release_s = 0.0;
    return m;
  }
  m.start = settled;
  const int nu = model.mesh.particles_warp(), nv = model.mesh.particles_weft();
  const Eigen::Vector3d centre = settled.x(model.mesh.Index(nu / 2, nv / 2));
  for (int p = 0; p < model.num_particles; ++p) {
    const bool loaded = kind == MotionKind::kPushWhole ? settled.mode[p] == ParticleMode::kFree
                                                       : (settled.x(p) - centre).norm() <= 0.02 + 1e-9;
    if (loaded) m.gripped.push_back(p);
  }
  if (kind == MotionKind::kPush || kind == MotionKind::kPushWhole) {
    const double weight_N = model.mass_kg.sum() * model.options.gravity_m_per_s2.norm();
    m.push_W_N = Eigen::Vector3d(0, 2.0 * weight_N, 0);  // normal to the hanging cloth
    double gripped_kg = 0.0;
    for (int p : m.gripped) gripped_kg += model.mass_kg[p];
    for (int p : m.gripped) {  // the disc: evenly; the whole cloth: by mass, as its weight
      m.push_share.push_back(kind == MotionKind::kPush ? 1.0 / static_cast<double>(m.gripped.size())
                                                       : model.mass_kg[p] / gripped_kg);
    }
    m.duration_s = 1.25;
    m.release_s = 0.25;
  } else {
    m.stretch_W_m = Eigen::Vector3d(0.01, 0, 0);  // sideways, in the cloth's plane
    m.stretch_s = 0.5;
    m.duration_s = 1.0;
    m.release_s = m.duration_s;  // the grip does work throughout
  }
  return m;
}

MotionTrace RunMotion(const Motion& motion, const FabricModel& model, const StepOptions& options,
                      const std::function<StepResult(FabricStepper&, FabricState&)>& step) {
  FabricState s = motion.start;
  FabricStepper stepper(model, options);
  const auto steps = std::llround(motion.duration_s / options.dt_s);
  const auto sample_every = std::max<long long>(1, std::llround(kSample_s / options.dt_s));
  MotionTrace t;
  t.dt_s = options.dt_s;
  auto sample = [&] {
    t.x_W_m.push_back(s.x_W_m);
    t.energy_J.push_back(TotalEnergy(model, s));
    t.largest_strain.push_back(LargestTensileStrain(model, s.x_W_m));
  };
  sample();
  t.peak_strain = t.largest_strain.back();
  double newton = 0.0, cg = 0.0;
  for (long long i = 1; i <= steps; ++i) {
    Drive(motion, static_cast<double>(i) * options.dt_s, &s);
    const StepResult r = step ? step(stepper, s) : stepper.Step(&s);
    newton += r.newton_iterations;
    cg += r.cg.iterations;
    t.peak_strain = std::max(t.peak_strain, LargestTensileStrain(model, s.x_W_m));
    if (i % sample_every == 0) sample();
  }
  t.newton_iterations_per_step = newton / static_cast<double>(steps);
  t.cg_iterations_per_step = cg / static_cast<double>(steps);
  t.step_halvings = s.diagnostics.step_halvings;
  t.newton_not_converged = s.diagnostics.newton_not_converged;
  t.nan_events = s.diagnostics.nan_events;
  return t;
}

MotionErrors CompareMotion(const Motion& motion, const MotionTrace& run, const MotionTrace& ref) {
  MotionErrors e;
  const double peak_ref = std::abs(ref.peak_strain);
  e.peak_strain_pct = 100.0 * std::abs(run.peak_strain - ref.peak_strain) / peak_ref;
  const double run_sample_s = std::max(run.dt_s, kSample_s), ref_sample_s = std::max(ref.dt_s, kSample_s);
  const auto stride = static_cast<std::size_t>(std::llround(run_sample_s / ref_sample_s));
  const auto [lo, hi] = std::minmax_element(ref.energy_J.begin(), ref.energy_J.end());
  const double energy_scale_J = std::max(*hi - *lo, 1e-15);
  double sum2 = 0.0;
  std::size_t count = 0;
  double lowest_since_release_J = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < run.x_W_m.size(); ++k) {
    const std::size_t r = k * stride;
    if (r >= ref.x_W_m.size()) break;
    sum2 += (run.x_W_m[k] - ref.x_W_m[r]).squaredNorm() / static_cast<double>(run.x_W_m[k].size() / 3);
    ++count;
    e.strain_in_time_pct =
        std::max(e.strain_in_time_pct, 100.0 * std::abs(run.largest_strain[k] - ref.largest_strain[r]) / peak_ref);
    e.energy_pct = std::max(e.energy_pct, 100.0 * std::abs(run.energy_J[k] - ref.energy_J[r]) / energy_scale_J);
    if (static_cast<double>(k) * run_sample_s >= motion.release_s - 1e-9) {
      lowest_since_release_J = std::min(lowest_since_release_J, run.energy_J[k]);
      e.energy_growth_pct =
          std::max(e.energy_growth_pct, 100.0 * (run.energy_J[k] - lowest_since_release_J) / energy_scale_J);
    }
  }
  e.position_rms_mm = 1e3 * std::sqrt(sum2 / static_cast<double>(std::max<std::size_t>(count, 1)));
  return e;
}

}  // namespace haptex::textile::validation
