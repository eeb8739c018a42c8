#include "launch/run_report.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "launch/force_log_reader.h"
#include "launch/gnuplot.h"
#include "launch/trace_export.h"

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

}  // namespace

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
                                  const std::vector<Recording>& recordings, const std::optional<ForceLog>& force_log) {
  const std::string dir = run_dir + "/plots";
  std::filesystem::create_directories(dir + "/data");
  std::vector<PlotResult> plots;
  const std::int64_t t0 = EarliestSendTimeNs(recordings);
  const auto seconds = [t0](const v1::Envelope& e) { return static_cast<double>(e.send_time_ns() - t0) * 1e-9; };

  // per finger: |F0| of the ForceModels, F_N of the TouchTraces, positions of the FingerStates
  std::map<int, std::vector<Sample>> model_force, normal_force;
  std::map<int, std::vector<std::pair<double, v1::Vec3>>> positions;
  std::map<int, std::vector<std::pair<double, int>>> states;
  // the last Health of each sender
  std::map<std::string, v1::Health> last_health;
  for (const Recording& r : recordings) {
    for (const v1::Envelope& e : r.envelopes) {
      const double t = seconds(e);
      if (e.has_force_model()) {
        for (const auto& m : e.force_model().fingers()) {
          model_force[m.finger()].push_back({t, Norm(m.f0_w_n())});
          states[m.finger()].push_back({t, static_cast<int>(m.contact_state())});
        }
      } else if (e.has_touch_trace()) {
        for (const auto& f : e.touch_trace().fingers()) normal_force[f.finger()].push_back({t, f.normal_force_n()});
      } else if (e.has_finger_states()) {
        for (const auto& f : e.finger_states().fingers()) positions[f.finger()].push_back({t, f.position_w_m()});
      } else if (e.has_health()) {
        last_health[e.sender()] = e.health();
      }
    }
  }
  for (auto* series : {&model_force, &normal_force}) {
    for (auto& [finger, samples] : *series) {
      std::sort(samples.begin(), samples.end(), [](const Sample& a, const Sample& b) { return a.t_s < b.t_s; });
    }
  }

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

  // 2. F_T/F_N vs time (Fig. 9): F_N from the TouchTrace, F_T from the ForceModel of the same finger
  //    at that time (|F0|^2 = F_N^2 + F_T^2)
  std::string ratio_plot;
  for (const auto& [finger, normals] : normal_force) {
    const auto& forces = model_force[finger];
    if (forces.empty()) continue;
    const std::string file = "friction_ratio_" + FingerName(finger) + ".dat";
    std::ofstream out(dir + "/data/" + file);
    std::size_t k = 0, rows = 0;
    for (const Sample& n : normals) {
      while (k + 1 < forces.size() && forces[k + 1].t_s <= n.t_s) ++k;
      if (n.value < 0.05) continue;  // no meaningful ratio without a normal force
      const double total = forces[k].value;
      const double tangential = std::sqrt(std::max(0.0, total * total - n.value * n.value));
      out << n.t_s << ' ' << tangential / n.value << '\n';
      ++rows;
    }
    if (rows > 0) ratio_plot += DataFile(file) + " using 1:2 with lines title '" + FingerName(finger) + "', ";
  }
  if (!ratio_plot.empty()) {
    plots.push_back(Draw("friction_ratio", dir,
                         "set title 'F_T / F_N (paper Fig. 9)'\nset xlabel 't [s]'\nset ylabel 'F_T/F_N'\nplot " +
                             ratio_plot.substr(0, ratio_plot.size() - 2) + "\n"));
  } else {
    plots.push_back(
        {"friction_ratio", "", "needs TouchTrace and ForceModel recordings with a normal force (local_contact)"});
  }

  // 3. tangential force vs elongation (Fig. 10), stretch scenes: from the pinch onset (state VIII
  //    or IX) the thumb's distance from where the pinch began against its |F0|
  const auto kind = scene.device().mock().user().kind();
  const bool stretches = kind == v1::MockUserScript::KIND_PINCH_AND_STRETCH || kind == v1::MockUserScript::KIND_DEMO;
  if (!stretches) {
    plots.push_back({"force_vs_elongation", "", "not a stretch scene"});
  } else {
    std::string plot;
    for (const auto& [finger, finger_states] : states) {
      const auto onset = std::find_if(finger_states.begin(), finger_states.end(), [](const auto& s) {
        return s.second == v1::CONTACT_STATE_VIII || s.second == v1::CONTACT_STATE_IX;
      });
      const auto& pos = positions[finger];
      if (onset == finger_states.end() || pos.empty()) continue;
      const std::string file = "force_vs_elongation_" + FingerName(finger) + ".dat";
      std::ofstream out(dir + "/data/" + file);
      std::size_t p = 0;
      while (p + 1 < pos.size() && pos[p + 1].first <= onset->first) ++p;
      const v1::Vec3 start = pos[p].second;
      std::size_t rows = 0;
      for (const Sample& f : model_force[finger]) {
        if (f.t_s < onset->first) continue;
        while (p + 1 < pos.size() && pos[p + 1].first <= f.t_s) ++p;
        const v1::Vec3& x = pos[p].second;
        out << Norm3(x.x() - start.x(), x.y() - start.y(), x.z() - start.z()) * 1e3 << ' ' << f.value << '\n';
        ++rows;
      }
      if (rows > 0) plot += DataFile(file) + " using 1:2 with points pt 7 ps 0.3 title '" + FingerName(finger) + "', ";
    }
    if (plot.empty()) {
      plots.push_back({"force_vs_elongation", "",
                       "needs a pinch (contact state VIII/IX) in the ForceModel recording and FingerStates"});
    } else {
      plots.push_back(Draw("force_vs_elongation", dir,
                           "set title 'Tangential force vs elongation (paper Fig. 10)'\nset xlabel 'elongation [mm]'\n"
                           "set ylabel 'force [N]'\nplot " +
                               plot.substr(0, plot.size() - 2) + "\n"));
    }
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
