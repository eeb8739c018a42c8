#pragma once
// Shared set-up of the contact tests: fabric patches, finger poses, scripted motions.

#include <memory>
#include <string>

#include <Eigen/Core>

#include "libs/contact/contact_options.h"
#include "libs/contact/finger_geometry.h"
#include "libs/contact/patch_simulation.h"
#include "libs/textile/kes_material.h"
#include "libs/textile/step_options.h"

namespace haptex::contact::testing {

/// Database fabric by name (data/fabrics), as material laws.
textile::FabricMaterial DatabaseMaterial(const std::string& name);

/// A square patch lying in the z = 0 plane centred on the origin (u along x, v along y), its
/// border fixed (a patch cut from a larger fabric), gravity along -z. `pretension_strain` > 0
/// places it stretched, like fabric in an embroidery hoop.
std::unique_ptr<PatchSimulation> MakeFlatPatch(const textile::FabricMaterial& material, double size_m,
                                               int particles_per_side, const ContactOptions& options,
                                               const textile::StepOptions& step, double pretension_strain = 0.0);

/// A pose whose pad (+z_F) faces `pad_normal_W` with the distal axis (+x_F) along `distal_W`
/// (libs/contact/finger_geometry.h, shared with the benchmarks).
using contact::PoseFacing;

/// Linear interpolation from a to b as t goes from t0 to t1 (clamped).
Eigen::Vector3d Ramp(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double t, double t0, double t1);

/// Default step options of a local patch at 1 kHz.
textile::StepOptions LocalStep(double dt_s = 0.001);

}  // namespace haptex::contact::testing
