#pragma once
// The fabrics and solver settings the accuracy-in-motion benchmarks compare (dynamic_accuracy,
// bench/peer's Bullet comparison): one definition for both, so their rows mean the same.

#include <algorithm>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "libs/scene/fabric_conversion.h"
#include "libs/textile/kes_material.h"
#include "libs/textile/step_options.h"
#include "libs/textile/validation.h"

namespace haptex::textile {

// The database denim, its laws on a light (10 g/m2) and a heavy (1 kg/m2) cloth, and scaled
// 100 times stiffer (nearly inextensible).
inline FabricMaterial FabricNamed(const std::string& name) {
  FabricMaterial denim = MaterialFromKes(scene::LoadKesFabric("wang2011_black_denim_11oz"));
  if (name == "denim") return denim;
  if (name == "light" || name == "heavy") {
    denim.density_kg_per_m2 = name == "light" ? 0.01 : 1.0;
    return denim;
  }
  if (name == "stiff") return validation::ScaleStiffness(denim, 100.0);
  throw std::invalid_argument("unknown fabric '" + name + "' (light, heavy, stiff, denim)");
}

// The solver settings compared. "default" is whatever step_options.h says.
inline std::map<std::string, StepOptions> Settings() {
  std::map<std::string, StepOptions> s;
  StepOptions bw;  // Baraff-Witkin's single linearised step, CG to 1e-2
  bw.newton_max_iterations = 1;
  bw.max_step_halvings = 0;
  bw.max_strain_rise_per_step = 0.0;
  bw.cg_tolerance = 1e-2;
  s["bw"] = bw;
  s["bw_cg1e-3"] = bw;
  s["bw_cg1e-3"].cg_tolerance = 1e-3;
  s["default"] = StepOptions{};
  // the single step, retaken as halves (down to 1/16) where the largest strain rises by more
  // than a point in one step: the cost only where the cloth is struck
  StepOptions strain_split = bw;
  strain_split.max_step_halvings = 4;
  strain_split.max_strain_rise_per_step = 0.01;
  s["bw_strain_split"] = strain_split;
  // the default's guard with a coarser bound (5 points): it lets the stiff cloth's disc push through
  StepOptions guard = StepOptions{};
  guard.max_strain_rise_per_step = 0.05;
  s["bw_guard0.05"] = guard;
  strain_split.newton_max_iterations = 8;
  s["newton_strain_split"] = strain_split;
  // Newton's iterations (at most 4) stopped at 0.3 of the force level: about two solves a step
  StepOptions loose = bw;
  loose.newton_max_iterations = 4;
  loose.newton_tolerance = 0.3;
  s["newton_loose0.3"] = loose;
  for (const double tol : {1e-2, 1e-3}) {
    StepOptions newton = bw;
    newton.newton_max_iterations = 8;
    newton.newton_tolerance = tol;
    const std::string suffix = tol == 1e-2 ? "" : "1e-3";
    s["newton" + suffix] = newton;
    newton.max_step_halvings = 4;
    s["newton" + suffix + "_split"] = newton;
    newton.max_step_halvings = 0;
    newton.newton_update_jacobian = true;
    s["newton" + suffix + "_full"] = newton;
  }
  // BDF2 (second order; it needs Newton's iterations, step_options.h)
  StepOptions bdf2 = bw;
  bdf2.method = Integrator::kBdf2;
  bdf2.newton_max_iterations = 2;
  s["bdf2_newton2"] = bdf2;
  bdf2.newton_max_iterations = 8;
  s["bdf2_newton"] = bdf2;
  bdf2.newton_tolerance = 1e-3;
  s["bdf2_newton1e-3"] = bdf2;
  return s;
}

/// The upper median of `v` (0 when empty): step times, iteration counts.
inline double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

/// The items of a comma-separated flag value ("1,2,5").
inline std::vector<std::string> Split(const std::string& list) {
  std::vector<std::string> out;
  std::stringstream in(list);
  for (std::string item; std::getline(in, item, ',');) {
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

}  // namespace haptex::textile
