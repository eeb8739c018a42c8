// A peer's cost at equal accuracy in motion: Bullet's soft body (Debian's libbullet-dev) against
// haptex on the same released swing (libs/textile/motion_accuracy.h): the database denim, 20 x 20
// cm on the same grid, the same particle masses and gravity, held along one edge, horizontal, let
// go. Both are judged against haptex's converged reference of the swing: the peak of the largest
// strain (Bullet: of its structural links; haptex: of its triangles) and the positions' RMS
// distance, sampled every millisecond. Bullet runs at 1 ms with its linear stiffness at the most
// (kLST = 1) and a range of position iterations; haptex at its settings of dynamic_accuracy.
// One row per run with the CPU time per step (median) and per simulated second.
//
//   bullet_swing [--mesh 41] [--reference-dt-ms 1] [--piterations 1,2,4,8,16,32,64]
//                [--settings bw:10,bdf2_newton:10,bdf2_newton:5]
//
// What Bullet does not model: bending stiffness (no bending links: a cloth as Bullet's examples make
// it), anisotropy and the fabric's tensile curve (its links are stiff constraints), and air drag
// (haptex's is 0.02 N s/m3: small beside the swing's). The strain it shows is its constraints'
// give, the accuracy a stiff cloth's step buys; a quiet machine for the times.

#include <BulletSoftBody/btDefaultSoftBodySolver.h>
#include <BulletSoftBody/btSoftBodyHelpers.h>
#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>
#include <BulletSoftBody/btSoftRigidDynamicsWorld.h>
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench/textile/accuracy_settings.h"
#include "libs/textile/motion_accuracy.h"
#include "libs/textile/validation.h"

namespace haptex::textile {
namespace {

using validation::ConvergedOptions;
using validation::MakeMotion;
using validation::Motion;
using validation::MotionKind;
using validation::MotionTrace;
using validation::RunMotion;

constexpr double kSide_m = 0.2;
constexpr double kSample_s = 1e-3;  // motion_accuracy's sampling

struct Row {
  std::string solver, setting;
  double dt_ms = 0, step_ms = 0, peak_strain = 0, rms_mm = 0;
};

// RMS over particles and samples of the distance to the reference's positions at the same times.
double PositionRmsMm(const std::vector<Eigen::VectorXd>& x_W_m, const MotionTrace& reference) {
  double sum2 = 0.0;
  std::size_t count = 0;
  for (std::size_t k = 0; k < x_W_m.size() && k < reference.x_W_m.size(); ++k) {
    sum2 += (x_W_m[k] - reference.x_W_m[k]).squaredNorm();
    count += static_cast<std::size_t>(x_W_m[k].size() / 3);
  }
  return count == 0 ? 0.0 : 1e3 * std::sqrt(sum2 / static_cast<double>(count));
}

Row RunBullet(const Motion& motion, const FabricModel& model, int piterations, const MotionTrace& reference) {
  const int nu = model.mesh.particles_warp(), nv = model.mesh.particles_weft();
  btSoftBodyRigidBodyCollisionConfiguration collision;
  btCollisionDispatcher dispatcher(&collision);
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver rigid_solver;
  btDefaultSoftBodySolver soft_solver;
  btSoftRigidDynamicsWorld world(&dispatcher, &broadphase, &rigid_solver, &collision, &soft_solver);
  const Eigen::Vector3d g = model.options.gravity_m_per_s2;
  world.setGravity(btVector3(g.x(), g.y(), g.z()));
  btSoftBodyWorldInfo& info = world.getWorldInfo();
  info.m_gravity = btVector3(g.x(), g.y(), g.z());
  info.air_density = 0;
  info.water_density = 0;
  info.m_sparsesdf.Initialize();

  const auto corner = [&](int i, int j) {
    const Eigen::Vector3d p = motion.start.x(model.mesh.Index(i, j));
    return btVector3(p.x(), p.y(), p.z());
  };
  // node ix + nu iy of the patch is particle Index(ix, iy): the same grid, corner to corner
  std::unique_ptr<btSoftBody> cloth(btSoftBodyHelpers::CreatePatch(info, corner(0, 0), corner(nu - 1, 0),
                                                                   corner(0, nv - 1), corner(nu - 1, nv - 1), nu, nv, 0,
                                                                   /*gendiags=*/true));
  cloth->m_materials[0]->m_kLST = 1.0;
  cloth->m_cfg.piterations = piterations;
  cloth->m_cfg.kDP = 0.0;  // no damping beyond the solver's own
  for (int p = 0; p < model.num_particles; ++p) {
    const btVector3& x = cloth->m_nodes[p].m_x;
    if ((Eigen::Vector3d(x.x(), x.y(), x.z()) - motion.start.x(p)).norm() > 1e-5) {
      throw std::logic_error("Bullet's patch does not number its nodes as haptex's grid");
    }
    cloth->setMass(p, motion.start.mode[p] == ParticleMode::kFree ? static_cast<btScalar>(model.mass_kg[p]) : 0);
  }
  world.addSoftBody(cloth.get());
  const double h_m = kSide_m / (nu - 1);
  std::vector<int> structural;
  for (int l = 0; l < cloth->m_links.size(); ++l) {
    if (std::abs(static_cast<double>(cloth->m_links[l].m_rl) - h_m) < 1e-6) structural.push_back(l);
  }

  const double dt_s = 1e-3;
  const auto steps = std::llround(motion.duration_s / dt_s);
  std::vector<double> step_ms;
  std::vector<Eigen::VectorXd> x_W_m;
  Row row{"bullet", "piterations " + std::to_string(piterations), 1.0};
  const auto sample = [&] {
    Eigen::VectorXd x(3 * model.num_particles);
    for (int p = 0; p < model.num_particles; ++p) {
      const btVector3& q = cloth->m_nodes[p].m_x;
      x.segment<3>(3 * p) = Eigen::Vector3d(q.x(), q.y(), q.z());
    }
    x_W_m.push_back(x);
    for (const int l : structural) {
      const btSoftBody::Link& link = cloth->m_links[l];
      const double length_m = static_cast<double>((link.m_n[0]->m_x - link.m_n[1]->m_x).length());
      row.peak_strain = std::max(row.peak_strain, length_m / static_cast<double>(link.m_rl) - 1.0);
    }
  };
  sample();
  for (long long i = 1; i <= steps; ++i) {
    const auto start = std::chrono::steady_clock::now();
    world.stepSimulation(static_cast<btScalar>(dt_s), 0);
    step_ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    sample();
  }
  world.removeSoftBody(cloth.get());
  row.step_ms = Median(step_ms);
  row.rms_mm = PositionRmsMm(x_W_m, reference);
  return row;
}

Row RunHaptex(const Motion& motion, const FabricModel& model, const std::string& name, double dt_ms,
              const MotionTrace& reference) {
  StepOptions options = Settings().at(name);
  options.dt_s = dt_ms * 1e-3;
  std::vector<double> step_ms;
  const MotionTrace run = RunMotion(motion, model, options, [&](FabricStepper& stepper, FabricState& s) {
    const auto start = std::chrono::steady_clock::now();
    const StepResult r = stepper.Step(&s);
    step_ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    return r;
  });
  // the run samples every step when steps are longer than a millisecond: the reference's samples at its times
  const auto stride = static_cast<std::size_t>(std::llround(std::max(options.dt_s, kSample_s) / kSample_s));
  std::vector<Eigen::VectorXd> x_at_reference_times;
  MotionTrace thinned = reference;
  thinned.x_W_m.clear();
  for (std::size_t k = 0; k < run.x_W_m.size() && k * stride < reference.x_W_m.size(); ++k) {
    thinned.x_W_m.push_back(reference.x_W_m[k * stride]);
  }
  return {"haptex", name, dt_ms, Median(step_ms), run.peak_strain, PositionRmsMm(run.x_W_m, thinned)};
}

int Main(int argc, char** argv) {
  std::map<std::string, std::string> flags = {{"--mesh", "41"},
                                              {"--reference-dt-ms", "1"},
                                              {"--piterations", "1,2,4,8,16,32,64"},
                                              {"--settings", "bw:10,bdf2_newton:10,bdf2_newton:5"}};
  for (int i = 1; i < argc; ++i) {
    const std::string flag = argv[i];
    if (!flags.count(flag) || i + 1 >= argc) {
      std::cerr << "usage: bullet_swing [--mesh 41] [--reference-dt-ms 1] [--piterations 1,2,4,...] "
                   "[--settings bw:10,bdf2_newton:5,...]\n";
      return 2;
    }
    flags[flag] = argv[++i];
  }
  const int mesh = std::stoi(flags["--mesh"]);
  const FabricModel model = BuildFabricModel(FabricNamed("denim"), {kSide_m, kSide_m, mesh, mesh});
  const Motion motion = MakeMotion(MotionKind::kSwing, model, MakeRestState(model));  // the swing starts flat
  const double reference_dt_s = std::stod(flags["--reference-dt-ms"]) * 1e-3;
  const MotionTrace reference = RunMotion(motion, model, ConvergedOptions(reference_dt_s));
  std::printf("denim swing, %d x %d, 1 s; reference: BDF2 converged at %.2f ms, peak strain %.4f %%\n", mesh, mesh,
              reference_dt_s * 1e3, 100.0 * reference.peak_strain);
  std::printf("%-7s %-16s %6s %9s %12s %12s %12s %9s\n", "solver", "setting", "dt_ms", "step_ms", "cpu_s_per_s",
              "peak_strain%", "error_pts", "rms_mm");
  const auto print = [&](const Row& r) {
    std::printf("%-7s %-16s %6.1f %9.3f %12.3f %12.4f %12.4f %9.2f\n", r.solver.c_str(), r.setting.c_str(), r.dt_ms,
                r.step_ms, r.step_ms / r.dt_ms, 100.0 * r.peak_strain,
                100.0 * std::abs(r.peak_strain - reference.peak_strain), r.rms_mm);
    std::fflush(stdout);
  };
  for (const std::string& item : Split(flags["--settings"])) {
    const auto colon = item.find(':');
    if (colon == std::string::npos) throw std::invalid_argument("a setting is NAME:STEP_MS, not " + item);
    print(RunHaptex(motion, model, item.substr(0, colon), std::stod(item.substr(colon + 1)), reference));
  }
  for (const std::string& n : Split(flags["--piterations"])) print(RunBullet(motion, model, std::stoi(n), reference));
  return 0;
}

}  // namespace
}  // namespace haptex::textile

int main(int argc, char** argv) {
  try {
    return haptex::textile::Main(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "bullet_swing: " << e.what() << "\n";
    return 2;
  }
}
