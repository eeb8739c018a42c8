#include "launch/run_report.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "launch/figure_curves.h"
#include "launch/force_log_reader.h"
#include "launch/gnuplot.h"
#include "launch/trace_export.h"
#include "libs/codec/message_conversion.h"
#include "libs/device/mock_grab_controller.h"
#include "libs/scene/cloth_setup.h"
#include "libs/scene/scene_contact.h"
#include "libs/scene/scene_device.h"

namespace haptex::launch {
namespace {

double Norm3(double x, double y, double z) { return std::sqrt(x * x + y * y + z * z); }
double Norm(const v1::Vec3& v) { return Norm3(v.x(), v.y(), v.z()); }

void Accumulate(FingerForceStats* s, double value) {
  ++s->samples;
  s->peak_n = std::max(s->peak_n, value);
  s->mean_n += (value - s->mean_n) / static_cast<double>(s->samples);
  s->final_n = value;
}

// Writes plots/data/NAME.gp and runs it inside plots/: the script names only fixed relative
// files (NAME.png, data/*.dat), never the run folder, whose path holds user text.
PlotResult Draw(const std::string& name, const std::string& dir, const std::string& commands) {
  const std::string script = "data/" + name + ".gp";
  {
    std::ofstream out(dir + "/" + script);
    out << "set terminal pngcairo size 1000,600 noenhanced\nset output '" << name
        << ".png'\nset grid\nset key outside\n"
        << commands;
    if (!out) return {name, "", "cannot write " + dir + "/" + script};
  }
  const std::string error = RunGnuplot(dir, script);
  if (!error.empty()) return {name, "", error};
  return {name, dir + "/" + name + ".png", ""};
}

// A data file's name as the scripts give it (relative to plots/).
std::string DataFile(const std::string& file) { return "'data/" + file + "'"; }

// Loop names come from other processes' Health: data, but kept to what a label may hold.
std::string LoopLabel(const std::string& name) {
  std::string label;
  for (const char c : name.substr(0, 40)) label += std::isalnum(static_cast<unsigned char>(c)) || c == '_' ? c : '_';
  return label.empty() ? "loop" : label;
}

struct Sample {
  double t_s;
  double value;
};

struct Touch {
  double t_s;
  double normal_N, tangential_N;                    // of the force the device gets
  double friction_normal_N, friction_tangential_N;  // what the friction law holds
  int state;
};

// A number as a plot's legend or the run's note shows it.
std::string Fixed(double value, int decimals) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", decimals, value);
  return text;
}

// The newest sample at or before t_s in a time-ordered series, from index *k on (moves *k).
template <class Series>
const auto* AtOrBefore(const Series& series, double t_s, std::size_t* k) {
  while (*k + 1 < series.size() && series[*k + 1].first <= t_s) ++*k;
  return *k < series.size() && series[*k].first <= t_s ? &series[*k].second : nullptr;
}

bool Pinched(int state) { return state == v1::CONTACT_STATE_VIII || state == v1::CONTACT_STATE_IX; }

// One FingerStates: the fingers' midpoint and the forces the device measured on them.
struct Grip {
  Eigen::Vector3d midpoint_W_m;
  Eigen::Vector3d measured_force_W_N;  ///< summed over the fingers
  double weaker_finger_force_N;        ///< the smaller of the fingers' measured |force|
};

// Fig. 10's samples: from the pinch's onset (model_states[first_state], grips[first_grip]) the force
// the device measured along the stretch s_W against how far the fingers' midpoint moved along it,
// over the loading only. The force is the device's, what the person feels: a ForceModel's F0 is
// the force at the pose predicted for it, and the bridge moves it along the model's stiffness to
// where the finger is.
std::vector<StretchSample> PinchLoading(const std::vector<std::pair<double, int>>& model_states,
                                        std::size_t first_state, const std::vector<std::pair<double, Grip>>& grips,
                                        std::size_t first_grip, const Eigen::Vector3d& s_W) {
  // the sensor's reading averaged over the last kForceAverage_s (a force sensor is noisy: the
  // mock's, +-0.1 N per axis)
  constexpr double kForceAverage_s = 0.02;
  constexpr double kHeldForce_N = 0.5;
  constexpr double kLoadedShare = 0.98;
  const Eigen::Vector3d start_W = grips[first_grip].second.midpoint_W_m;
  std::vector<StretchSample> samples;
  std::size_t k = first_state, window_first = first_grip;
  Eigen::Vector3d window_sum_N = Eigen::Vector3d::Zero();
  for (std::size_t i = first_grip; i < grips.size(); ++i) {
    window_sum_N += grips[i].second.measured_force_W_N;
    while (grips[window_first].first < grips[i].first - kForceAverage_s) {
      window_sum_N -= grips[window_first++].second.measured_force_W_N;
    }
    const int* state = AtOrBefore(model_states, grips[i].first, &k);
    // a pinch the device holds: the model says so and the device presses both fingers (at the
    // run's end it lets go of the force while the model still says pinched)
    if (state == nullptr || !Pinched(*state) || grips[i].second.weaker_finger_force_N < kHeldForce_N) continue;
    const Eigen::Vector3d force_W_N = window_sum_N / static_cast<double>(i + 1 - window_first);
    samples.push_back({(grips[i].second.midpoint_W_m - start_W).dot(s_W), -force_W_N.dot(s_W)});
  }
  // The loading, as a tensile curve is: until the elongation first comes within 2 % of its
  // largest. The rest is the hold, where the fingers settle on the user's grip springs over the
  // pull's last tenths of a millimetre while the strip under them relaxes.
  const auto largest = std::max_element(samples.begin(), samples.end(),
                                        [](const auto& a, const auto& b) { return a.elongation_m < b.elongation_m; });
  if (largest != samples.end()) {
    const double loaded_m = kLoadedShare * largest->elongation_m;
    const auto loaded = std::find_if(samples.begin(), samples.end(),
                                     [loaded_m](const StretchSample& x) { return x.elongation_m >= loaded_m; });
    samples.erase(loaded + 1, samples.end());
  }
  return samples;
}

}  // namespace

FigureReference FigureReferenceFromScene(const scene::LoadedScene& loaded) {
  FigureReference r;
  const contact::ContactOptions contact = scene::ContactOptionsFromScene(loaded);
  r.has_friction = true;
  r.mu_static = contact.finger_fabric.mu_static;
  r.mu_dynamic = contact.finger_fabric.mu_dynamic;
  const v1::Scene& s = loaded.scene;
  const device::ScriptParams user = scene::MockScriptFromScene(s, device::MockControllerConfig{});
  const Eigen::Isometry3d X_WD = scene::DeviceFrameInWorld(s.device(), Eigen::Isometry3d::Identity());
  const Eigen::Vector3d stretch_W = X_WD.linear() * user.stretch_D_m;
  if (stretch_W.norm() > 0.0) r.stretch_W = stretch_W.normalized();

  // Fig. 10 is the paper's tensile test: a strip held by a clamp across the pull. Its force is
  // the fabric's tensile curve only when the clamp is a line across the stretch and the fingers
  // grip the strip's whole width; a cloth hung from its top edge and pulled sideways is sheared.
  const scene::ClothSetup setup = scene::MakeClothSetup(loaded);
  const int nu = setup.grid.particles_warp, nv = setup.grid.particles_weft;
  const double du = setup.grid.length_warp_m / (nu - 1), dv = setup.grid.width_weft_m / (nv - 1);
  const Eigen::Vector3d u_W = setup.placement.axis_u_W, v_W = setup.placement.axis_v_W;
  if (setup.fixed_particles.empty()) {
    r.no_strip = "nothing holds the cloth";
    return r;
  }
  double clamp_min = 1e300, clamp_max = -1e300;
  for (const int k : setup.fixed_particles) {
    const Eigen::Vector3d x_W = setup.placement.origin_W + (k % nu) * du * u_W + (k / nu) * dv * v_W;
    clamp_min = std::min(clamp_min, x_W.dot(r.stretch_W));
    clamp_max = std::max(clamp_max, x_W.dot(r.stretch_W));
  }
  if (clamp_max - clamp_min > 1e-9) {
    r.no_strip = "the cloth is held along the stretch (its fixed particles span " +
                 Fixed(1e3 * (clamp_max - clamp_min), 1) + " mm along it), not clamped across it: no tensile strip";
    return r;
  }
  const textile::StrainCurve* curve = nullptr;
  if (std::abs(r.stretch_W.dot(u_W)) > 1.0 - 1e-9) {
    r.strip = ClampedStrip{clamp_min, setup.grid.width_weft_m, "warp", {}};
    curve = &setup.material.tensile_warp;
  } else if (std::abs(r.stretch_W.dot(v_W)) > 1.0 - 1e-9) {
    r.strip = ClampedStrip{clamp_min, setup.grid.length_warp_m, "weft", {}};
    curve = &setup.material.tensile_weft;
  } else {
    r.no_strip = "the stretch runs along neither material axis of the cloth";
    return r;
  }
  const double grip_m = 2.0 * std::min(contact.thumb.radius_m, contact.index.radius_m);
  const double pinch_along_m = (X_WD * user.fabric_point_D_m).dot(r.stretch_W);
  if (r.strip->width_m > grip_m + 1e-9) {
    r.no_strip = "the strip (" + Fixed(1e3 * r.strip->width_m, 1) + " mm across) is wider than the fingers grip (" +
                 Fixed(1e3 * grip_m, 1) + " mm): its tension is not even across it";
  } else if (pinch_along_m <= clamp_min) {
    r.no_strip = "the fingers pull towards the clamp, not away from it";
  }
  if (!r.no_strip.empty()) {
    r.strip.reset();
    return r;
  }
  r.strip->force_per_width_N_per_m = [law = *curve](double strain) { return law.Value(strain); };
  return r;
}

std::string RomanState(int state) {
  static const char* names[] = {"unspecified", "I", "II", "III", "IV", "V", "VI", "VII", "VIII", "IX"};
  return state >= 0 && state <= 9 ? names[state] : "unknown";
}

std::optional<ForceLog> ReadForceLog(const std::string& path) {
  const std::vector<device::ForceLogRow> rows = ReadForceLogRows(path);
  if (rows.empty()) return std::nullopt;
  ForceLog log;
  for (const device::ForceLogRow& row : rows) {
    log.t_s.push_back(static_cast<double>(row.time_ns - rows.front().time_ns) * 1e-9);
    for (int f = 0; f < 2; ++f) {
      const double n = row.CommandedNormN(f);
      const auto& previous = log.commanded[static_cast<std::size_t>(f)];
      if (n == 0.0 && !previous.empty() && previous.back() >= ForceLog::kDropoutFromN) ++log.dropouts;
      log.commanded[static_cast<std::size_t>(f)].push_back(n);
      Accumulate(&log.stats[static_cast<std::size_t>(f)], n);
    }
  }
  return log;
}

RecordingAnalysis AnalyseRecordings(const std::vector<Recording>& recordings) {
  RecordingAnalysis a;
  for (const Recording& r : recordings) {
    for (const v1::Envelope& e : r.envelopes) {
      switch (e.body_case()) {
        case v1::Envelope::kForceModel:
          ++a.force_models;
          for (const v1::FingerForceModel& m : e.force_model().fingers()) {
            const int state = static_cast<int>(m.contact_state());
            if (state >= 0 && state <= 9) ++a.contact_states[static_cast<std::size_t>(state)];
            Accumulate(&a.model_forces[FingerName(m.finger())], Norm(m.f0_w_n()));
          }
          break;
        case v1::Envelope::kTouchTrace:
          ++a.touch_traces;
          break;
        case v1::Envelope::kHealth:
          ++a.health_messages;
          break;
        case v1::Envelope::kFingerStates:
          ++a.finger_states;
          break;
        default:
          break;
      }
    }
  }
  return a;
}

std::vector<PlotResult> MakePlots(const std::string& run_dir, const v1::Scene& scene,
                                  const std::vector<Recording>& recordings, const std::optional<ForceLog>& force_log,
                                  const FigureReference& reference) {
  const std::string dir = run_dir + "/plots";
  std::filesystem::create_directories(dir + "/data");
  std::vector<PlotResult> plots;
  const std::int64_t t0 = EarliestSendTimeNs(recordings);
  const auto seconds = [t0](const v1::Envelope& e) { return static_cast<double>(e.send_time_ns() - t0) * 1e-9; };

  // per finger: |F0| of the ForceModels, F_N and state of the TouchTraces; per ForceModel the
  // pinch state, per FingerStates the fingers' midpoint and the forces the device measured on them
  std::map<int, std::vector<Sample>> model_force;
  std::map<int, std::vector<Touch>> touches;
  std::vector<std::pair<double, int>> model_states;  // t, the fingers' highest contact state
  std::vector<std::pair<double, Grip>> grips;
  // the last Health of each sender
  std::map<std::string, v1::Health> last_health;
  for (const Recording& r : recordings) {
    for (const v1::Envelope& e : r.envelopes) {
      const double t = seconds(e);
      if (e.has_force_model()) {
        int state = 0;
        for (const auto& m : e.force_model().fingers()) {
          model_force[m.finger()].push_back({t, Norm(m.f0_w_n())});
          state = std::max(state, static_cast<int>(m.contact_state()));
        }
        model_states.push_back({t, state});
      } else if (e.has_touch_trace()) {
        for (const auto& f : e.touch_trace().fingers()) {
          touches[f.finger()].push_back({t, f.normal_force_n(), f.tangential_force_n(), f.friction_normal_force_n(),
                                         f.friction_tangential_force_n(), static_cast<int>(f.contact_state())});
        }
      } else if (e.has_finger_states() && e.finger_states().fingers_size() > 0) {
        Eigen::Vector3d sum_m = Eigen::Vector3d::Zero(), sum_N = Eigen::Vector3d::Zero();
        double weaker_N = std::numeric_limits<double>::infinity();
        for (const auto& f : e.finger_states().fingers()) {
          sum_m += codec::ToEigen(f.position_w_m());
          sum_N += codec::ToEigen(f.measured_force_w_n());
          weaker_N = std::min(weaker_N, Norm(f.measured_force_w_n()));
        }
        grips.push_back({t, {sum_m / e.finger_states().fingers_size(), sum_N, weaker_N}});
      } else if (e.has_health()) {
        last_health[e.sender()] = e.health();
      }
    }
  }
  const auto by_time = [](const auto& a, const auto& b) { return a.first < b.first; };
  for (auto& [finger, samples] : model_force) {
    std::sort(samples.begin(), samples.end(), [](const Sample& a, const Sample& b) { return a.t_s < b.t_s; });
  }
  for (auto& [finger, samples] : touches) {
    std::sort(samples.begin(), samples.end(), [](const Touch& a, const Touch& b) { return a.t_s < b.t_s; });
  }
  std::sort(model_states.begin(), model_states.end(), by_time);
  std::sort(grips.begin(), grips.end(), by_time);

  // 1. forces per finger vs time: the ForceModels' F0, else what the mock's fingers felt
  if (!model_force.empty()) {
    std::string plot = "set title 'Force per finger (ForceModel F0)'\nset xlabel 't [s]'\nset ylabel '|F0| [N]'\nplot ";
    for (const auto& [finger, samples] : model_force) {
      const std::string file = "forces_" + FingerName(finger) + ".dat";
      std::ofstream out(dir + "/data/" + file);
      for (const Sample& s : samples) out << s.t_s << ' ' << s.value << '\n';
      plot += DataFile(file) + " using 1:2 with lines title '" + FingerName(finger) + "', ";
    }
    plots.push_back(Draw("forces", dir, plot.substr(0, plot.size() - 2) + "\n"));
  } else if (force_log) {
    std::ofstream out(dir + "/data/forces_felt.dat");
    const std::size_t step = std::max<std::size_t>(1, force_log->t_s.size() / 5000);
    for (std::size_t i = 0; i < force_log->t_s.size(); i += step) {
      out << force_log->t_s[i] << ' ' << force_log->commanded[0][i] << ' ' << force_log->commanded[1][i] << '\n';
    }
    out.close();
    plots.push_back(Draw("forces", dir,
                         "set title 'Force commanded to each finger (mock controller force log)'\nset xlabel 't [s]'\n"
                         "set ylabel '|F| [N]'\nplot " +
                             DataFile("forces_felt.dat") + " using 1:2 with lines title 'thumb', " +
                             DataFile("forces_felt.dat") + " using 1:3 with lines title 'index'\n"));
  } else {
    plots.push_back({"forces", "", "no ForceModel recorded and no mock controller force log"});
  }

  // 2. F_T/F_N vs time (Fig. 9), from each tick's TouchTrace: the friction law's ratio (the
  //    paper's F^T/F^N, what sticks up to mu_s and slides at mu_d) and the device's (its force
  //    includes the fabric's tension on the finger); measured on the finger with the most
  //    one-finger contact, against the scene's mu_s and mu_d
  std::string ratio_plot;
  std::vector<FrictionSample> rubbing, rubbing_device;  // the finger the figure measures
  std::string rubbing_finger;
  for (const auto& [finger, finger_touches] : touches) {
    const std::string file = "friction_ratio_" + FingerName(finger) + ".dat";
    std::ofstream out(dir + "/data/" + file);
    std::vector<FrictionSample> series, device;
    std::size_t one_finger = 0;
    for (const Touch& n : finger_touches) {
      // no meaningful ratio without a normal force
      if (n.friction_normal_N < StickSlipOptions{}.min_normal_N) continue;
      series.push_back({n.t_s, n.friction_normal_N, n.friction_tangential_N, n.state});
      if (n.normal_N >= StickSlipOptions{}.min_normal_N) device.push_back({n.t_s, n.normal_N, n.tangential_N, n.state});
      out << n.t_s << ' ' << n.friction_tangential_N / n.friction_normal_N << ' '
          << (n.normal_N > 0.0 ? n.tangential_N / n.normal_N : 0.0) << ' ' << n.state << '\n';
      one_finger += n.state == v1::CONTACT_STATE_IV || n.state == v1::CONTACT_STATE_V;
    }
    if (!series.empty()) {
      ratio_plot += DataFile(file) + " using 1:2 with lines lw 2 title '" + FingerName(finger) + " (friction)', " +
                    DataFile(file) + " using 1:3 with lines title '" + FingerName(finger) + " (device force)', ";
    }
    if (one_finger > 0 && series.size() > rubbing.size()) {
      rubbing = std::move(series);
      rubbing_device = std::move(device);
      rubbing_finger = FingerName(finger);
    }
  }
  if (!ratio_plot.empty()) {
    std::string references;
    if (reference.has_friction) {
      references = ", " + Fixed(reference.mu_static, 4) +
                   " with lines dt 2 lw 2 lc 'red' title 'mu_s = " + Fixed(reference.mu_static, 2) + "', " +
                   Fixed(reference.mu_dynamic, 4) +
                   " with lines dt 3 lw 2 lc 'blue' title 'mu_d = " + Fixed(reference.mu_dynamic, 2) + "'";
    }
    PlotResult plot = Draw("friction_ratio", dir,
                           "set title 'F_T / F_N of each finger (paper Fig. 9: sticks up to mu_s, slides at mu_d)'\n"
                           "set xlabel 't [s]'\nset ylabel 'F_T/F_N'\nset yrange [0:*]\nplot " +
                               ratio_plot.substr(0, ratio_plot.size() - 2) + references + "\n");
    if (!rubbing.empty()) {
      const StickSlipFigure f = MeasureStickSlip(rubbing);
      const StickSlipFigure device = MeasureStickSlip(rubbing_device);
      if (reference.has_friction) plot.measured = {{"mu_s", reference.mu_static}, {"mu_d", reference.mu_dynamic}};
      plot.measured.insert(plot.measured.end(), {{"breakaways", static_cast<double>(f.breakaways)},
                                                 {"stick_peak_first", f.first_peak},
                                                 {"stick_peak_first_t_s", f.first_peak_t_s},
                                                 {"stick_peak_min", f.peak_min},
                                                 {"stick_peak_median", f.peak_median},
                                                 {"stick_peak_max", f.peak_max},
                                                 {"slide_samples", static_cast<double>(f.slide_samples)},
                                                 {"slide_median", f.slide_median},
                                                 {"slide_p10", f.slide_p10},
                                                 {"slide_p90", f.slide_p90},
                                                 {"device_breakaways", static_cast<double>(device.breakaways)},
                                                 {"device_stick_peak_first", device.first_peak},
                                                 {"device_stick_peak_median", device.peak_median},
                                                 {"device_stick_peak_max", device.peak_max},
                                                 {"device_slide_median", device.slide_median}});
      plot.note = rubbing_finger + ": " + std::to_string(f.breakaways) + " break-aways, friction's stick peak " +
                  Fixed(f.first_peak, 3) + " (all " + Fixed(f.peak_min, 3) + ".." + Fixed(f.peak_max, 3) + ")" +
                  (reference.has_friction ? " against mu_s " + Fixed(reference.mu_static, 3) : "") + ", sliding " +
                  Fixed(f.slide_median, 3) + " (p10 " + Fixed(f.slide_p10, 3) + ", p90 " + Fixed(f.slide_p90, 3) + ")" +
                  (reference.has_friction ? " against mu_d " + Fixed(reference.mu_dynamic, 3) : "") +
                  "; the device's force: peak " + Fixed(device.first_peak, 3) + " (median " +
                  Fixed(device.peak_median, 3) + "), sliding " + Fixed(device.slide_median, 3);
    }
    plots.push_back(plot);
  } else {
    plots.push_back({"friction_ratio", "", "needs TouchTrace recordings with a normal force (local_contact)"});
  }

  // 3. force vs elongation (Fig. 10), stretch scenes: from the pinch onset (state VIII or IX) the
  //    fingers' pull along the stretch (the force holding them back, summed over both) against how
  //    far their midpoint moved along it; beside the fabric's tensile curve when the cloth is a
  //    strip clamped across the stretch (FigureReference). PinchLoading picks the samples: the
  //    device's force, over the loading.
  const auto kind = scene.device().mock().user().kind();
  const bool stretches = kind == v1::MockUserScript::KIND_PINCH_AND_STRETCH || kind == v1::MockUserScript::KIND_DEMO;
  const auto onset =
      std::find_if(model_states.begin(), model_states.end(), [](const auto& m) { return Pinched(m.second); });
  std::size_t g = 0;
  const Grip* start = onset == model_states.end() ? nullptr : AtOrBefore(grips, onset->first, &g);
  const Eigen::Vector3d& s_W = reference.stretch_W;
  const std::vector<StretchSample> samples =
      stretches && start != nullptr
          ? PinchLoading(model_states, static_cast<std::size_t>(onset - model_states.begin()), grips, g, s_W)
          : std::vector<StretchSample>{};
  if (!stretches) {
    plots.push_back({"force_vs_elongation", "", "not a stretch scene"});
  } else if (start == nullptr) {
    plots.push_back({"force_vs_elongation", "",
                     "needs a pinch (contact state VIII/IX) in the ForceModel recording and FingerStates"});
  } else if (samples.empty()) {
    plots.push_back({"force_vs_elongation", "", "no sample while the device pressed both pinching fingers"});
  } else {
    const Eigen::Vector3d start_W = start->midpoint_W_m;
    {
      std::ofstream out(dir + "/data/force_vs_elongation.dat");
      for (const StretchSample& sample : samples) out << sample.elongation_m * 1e3 << ' ' << sample.force_N << '\n';
    }
    std::string commands;
    PlotResult plot;
    if (reference.strip) {
      // the pinched point was at the strip's rest length from the clamp (the strip hangs slack
      // until the fingers pull)
      const TensileStrip strip{start_W.dot(s_W) - reference.strip->clamp_along_stretch_m, reference.strip->width_m,
                               reference.strip->force_per_width_N_per_m};
      const ForceElongationFigure f = CompareWithTensileCurve(samples, strip);
      {
        std::ofstream out(dir + "/data/tensile_curve.dat");
        for (int i = 0; i <= 100; ++i) {
          const double e_m = f.max_elongation_m * i / 100.0;
          out << e_m * 1e3 << ' ' << StripForceN(strip, e_m) << '\n';
        }
      }
      commands =
          "set title 'Force along the pull vs elongation of the clamped strip, and the fabric tensile curve "
          "(paper Fig. 10)'\nset xlabel 'elongation of the strip [mm] (strain = elongation / " +
          Fixed(1e3 * strip.rest_length_m, 1) + " mm)'\nset ylabel 'F_T along the pull [N]'\nplot " +
          DataFile("force_vs_elongation.dat") +
          " using 1:2 with points pt 7 ps 0.3 title 'device-measured (sum, 20 ms mean)', " +
          DataFile("tensile_curve.dat") + " using 1:2 with lines lw 2 title '" + reference.strip->direction +
          " tensile curve x " + Fixed(1e3 * strip.width_m, 1) + " mm'\n";
      plot = Draw("force_vs_elongation", dir, commands);
      plot.measured = {{"rest_length_m", strip.rest_length_m},
                       {"width_m", strip.width_m},
                       {"samples", static_cast<double>(f.samples)},
                       {"max_elongation_m", f.max_elongation_m},
                       {"max_strain", f.max_elongation_m / strip.rest_length_m},
                       {"curve_peak_N", f.curve_peak_N},
                       {"rms_difference_N", f.rms_difference_N},
                       {"max_difference_N", f.max_difference_N},
                       {"rms_percent_of_peak", f.rms_percent_of_peak}};
      plot.note = "strip " + Fixed(1e3 * strip.rest_length_m, 1) + " x " + Fixed(1e3 * strip.width_m, 1) + " mm (" +
                  reference.strip->direction + "), pulled " + Fixed(1e3 * f.max_elongation_m, 2) + " mm (" +
                  Fixed(100.0 * f.max_elongation_m / strip.rest_length_m, 2) + " %): fabric " +
                  Fixed(f.curve_peak_N, 3) + " N there, RMS difference " + Fixed(f.rms_difference_N, 4) +
                  " N = " + Fixed(f.rms_percent_of_peak, 1) + " % of it over " + std::to_string(f.samples) + " samples";
    } else {
      commands =
          "set title 'Pinch: force along the stretch vs the fingers displacement since the pinch (not a "
          "tensile test)'\nset xlabel 'displacement along the stretch [mm]'\n"
          "set ylabel 'force along the stretch, both fingers [N]'\nplot " +
          DataFile("force_vs_elongation.dat") +
          " using 1:2 with points pt 7 ps 0.3 title 'device-measured (sum, 20 ms mean)'\n";
      plot = Draw("force_vs_elongation", dir, commands);
      plot.note = "no tensile reference: " + (reference.no_strip.empty() ? "not given" : reference.no_strip);
    }
    plots.push_back(plot);
  }

  // 4. loop periods: p50/p99/max of each loop from the last Health of each service
  {
    std::ofstream out(dir + "/data/loop_periods.dat");
    std::size_t rows = 0;
    for (const auto& [sender, health] : last_health) {
      for (const v1::LoopStats& l : health.loops()) {
        out << '"' << LoopLabel(l.name()) << "\" " << l.period_p50_us() << ' ' << l.period_p99_us() << ' '
            << l.period_max_us() << '\n';
        ++rows;
      }
    }
    out.close();
    if (rows == 0) {
      plots.push_back({"loop_periods", "", "no Health with loop statistics recorded"});
    } else {
      plots.push_back(
          Draw("loop_periods", dir,
               "set title 'Loop period per service (p50, p99, max; from Health)'\nset style data histogram\n"
               "set style histogram clustered\nset style fill solid 0.7\nset logscale y\n"
               "set ylabel 'period [us]'\nplot " +
                   DataFile("loop_periods.dat") +
                   " using 2:xtic(1) title 'p50', '' using 3 title 'p99', "
                   "'' using 4 title 'max'\n"));
    }
  }
  return plots;
}

}  // namespace haptex::launch
