#include "cli/sim_command.h"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>

#include "launch/json_writer.h"
#include "launch/run_folder.h"
#include "libs/base/clock.h"
#include "libs/runtime/latency_histogram.h"
#include "libs/scene/cloth_setup.h"
#include "libs/textile/fabric_stepper.h"

namespace haptex::cli {
namespace {

struct SimOptions {
  std::string scene;
  double duration_s = 0;
  std::string out;
  bool quiet = false;
};

// A new folder runs/sim-SLUG-TIME (the scene's name made one safe path component; -2, -3, ... when
// taken), as for haptex launch.
std::string DefaultOutDir(const std::string& scene_name) {
  const auto now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  char stamp[32];
  std::strftime(stamp, sizeof(stamp), "%Y%m%d-%H%M%S", std::localtime(&now));
  return launch::CreateUniqueRunFolder("runs", launch::RunFolderStem("sim-" + scene_name, stamp, ""));
}

void CheckWritten(const std::ofstream& out, const std::string& path) {
  if (!out) throw std::runtime_error("could not write " + path);
}

void WriteParticles(const std::string& path, const textile::FabricModel& model, const textile::FabricState& state) {
  std::ofstream out(path);
  out.precision(9);
  out << "id,u,v,x,y,z\n";
  for (int p = 0; p < model.num_particles; ++p) {
    const auto& uv = model.mesh.rest_uv_m(p);
    const auto x = state.x(p);
    out << p << ',' << uv(0) << ',' << uv(1) << ',' << x(0) << ',' << x(1) << ',' << x(2) << '\n';
  }
  out.flush();
  CheckWritten(out, path);
}

void WriteObj(const std::string& path, const textile::FabricModel& model, const textile::FabricState& state) {
  std::ofstream out(path);
  out.precision(9);
  out << "# haptex fabric, world frame [m]\n";
  for (int p = 0; p < model.num_particles; ++p) {
    const auto x = state.x(p);
    out << "v " << x(0) << ' ' << x(1) << ' ' << x(2) << '\n';
  }
  for (const auto& t : model.mesh.triangles()) out << "f " << t[0] + 1 << ' ' << t[1] + 1 << ' ' << t[2] + 1 << '\n';
  out.flush();
  CheckWritten(out, path);
}

int Sim(const SimOptions& options) {
  const scene::FabricDatabase fabrics(scene::FabricDatabase::DefaultDirectory());
  const scene::LoadedScene loaded = scene::LoadScene(options.scene, fabrics);
  const double duration_s = options.duration_s > 0 ? options.duration_s : loaded.scene.duration_s();
  if (!(duration_s > 0)) {
    throw std::invalid_argument("sim needs a duration: --duration S or duration_s in the scene");
  }
  const scene::ClothSetup setup = scene::MakeClothSetup(loaded);
  scene::ClothInstance cloth = scene::MakeClothInstance(setup);
  const scene::SceneLoads loads(loaded.scene, cloth.model);
  textile::FabricStepper stepper(cloth.model, setup.step_options);

  const double dt = setup.step_options.dt_s;
  const auto steps = static_cast<std::int64_t>(std::ceil(duration_s / dt - 1e-9));
  const std::string out_dir = options.out.empty() ? DefaultOutDir(loaded.scene.name()) : options.out;
  std::filesystem::create_directories(out_dir);
  if (!options.quiet) {
    std::cerr << "sim " << loaded.scene.name() << ": fabric " << loaded.fabric.name() << ", "
              << setup.grid.particles_warp << "x" << setup.grid.particles_weft << " particles, " << steps
              << " steps of " << dt * 1e3 << " ms (" << textile::IntegratorName(setup.step_options.method) << ")\n";
  }

  runtime::LatencyHistogram step_time;
  std::int64_t status_counts[4] = {0, 0, 0, 0};
  const std::int64_t start_ns = base::SteadyNowNs();
  std::int64_t next_progress_ns = start_ns + 1000000000;
  for (std::int64_t k = 0; k < steps; ++k) {
    loads.Apply(cloth.state.time_s, &cloth.state);
    const std::int64_t t0 = base::SteadyNowNs();
    const textile::StepResult result = stepper.Step(&cloth.state);
    const std::int64_t t1 = base::SteadyNowNs();
    step_time.Record(t1 - t0);
    ++status_counts[static_cast<int>(result.status)];
    if (!options.quiet && t1 > next_progress_ns) {
      next_progress_ns = t1 + 1000000000;
      std::cerr << "  t = " << cloth.state.time_s << " s (" << (100 * (k + 1)) / steps << " %)\n";
    }
  }
  const double wall_s = static_cast<double>(base::SteadyNowNs() - start_ns) * 1e-9;

  WriteParticles(out_dir + "/particles.csv", cloth.model, cloth.state);
  WriteObj(out_dir + "/mesh.obj", cloth.model, cloth.state);
  const auto& diag = cloth.state.diagnostics;
  launch::JsonWriter json;
  json.BeginObject()
      .Field("scene", loaded.scene.name())
      .Field("fabric", loaded.fabric.name())
      .Field("integrator", textile::IntegratorName(setup.step_options.method))
      .Field("particles", cloth.model.num_particles)
      .Field("triangles", static_cast<std::int64_t>(cloth.model.triangles.size()))
      .Field("steps", steps)
      .Field("dt_s", dt)
      .Field("simulated_s", cloth.state.time_s)
      .Field("wall_s", wall_s)
      .Field("step_ms_p50", step_time.Percentile(0.5) * 1e-6)
      .Field("step_ms_p99", step_time.Percentile(0.99) * 1e-6)
      .Field("step_ms_max", static_cast<double>(step_time.max_ns()) * 1e-6)
      .Field("kinetic_energy_end_J", textile::KineticEnergy(cloth.model, cloth.state))
      .Field("max_speed_end_m_per_s", textile::MaxSpeed(cloth.state))
      .Field("nan_count", diag.nan_events)
      .Field("cg_not_converged", diag.cg_not_converged)
      .Field("newton_not_converged", diag.newton_not_converged)
      .Field("step_halvings", diag.step_halvings)
      .Field("speed_capped", diag.speed_capped)
      .Field("steps_ok", status_counts[0])
      .EndObject();
  {
    std::ofstream summary(out_dir + "/summary.json");
    summary << json.str() << "\n";
    summary.flush();
    CheckWritten(summary, out_dir + "/summary.json");
  }
  std::cout << "sim " << loaded.scene.name() << ": " << steps << " steps in " << wall_s << " s wall (step p50 "
            << step_time.Percentile(0.5) * 1e-6 << " ms, p99 " << step_time.Percentile(0.99) * 1e-6
            << " ms), NaN events " << diag.nan_events << "\n  wrote " << out_dir
            << "/{particles.csv,mesh.obj,summary.json}\n";
  return diag.nan_events == 0 ? 0 : 1;
}

}  // namespace

void AddSimCommand(CLI::App& app, int* exit_code) {
  auto options = std::make_shared<SimOptions>();
  CLI::App* sim = app.add_subcommand("sim", "Simulate a scene's fabric alone, offline, as fast as it goes");
  sim->add_option("scene", options->scene, "scene file (.textproto)")->required();
  sim->add_option("--duration", options->duration_s, "simulated seconds (default: the scene's duration_s)")
      ->check(CLI::Range(1e-6, 1e6));
  sim->add_option("--out", options->out, "output folder (default: runs/sim-SCENE-TIME)");
  sim->add_flag("--quiet", options->quiet, "no progress on stderr");
  sim->callback([options, exit_code] { *exit_code = Sim(*options); });
}

}  // namespace haptex::cli
