#pragma once
// Scenarios shared by the textile validation tests and the benchmarks (bench/textile,
// docs/validation.md): a composite test fabric, stiffness scaling, the stand's rows, running to
// rest, the analytic elongation of a hanging strip, and seeded perturbations. Pure, like the core;
// a separate library (haptex::textile_validation), not part of what the services link.

#include <vector>

#include "libs/textile/fabric_model.h"
#include "libs/textile/fabric_state.h"
#include "libs/textile/fabric_stepper.h"
#include "libs/textile/kes_fabric.h"
#include "libs/textile/kes_material.h"
#include "libs/textile/strain_curve.h"

namespace haptex::textile::validation {

/// A test-only composite "stiff woven": the KES tensile values of Kumari & Khurana 2016 denim B
/// (EMT 5.735 %, LT 0.655, both directions; docs/physics-reference.md section 1.2) with the mass,
/// shear and bending of the Wang 2011 11 oz denim (the Kumari table's W is unusable). Not a
/// database fabric.
kes::Fabric CompositeDenim();

/// `m` with every stiffness (tensile, shear, bending) multiplied by `factor`.
FabricMaterial ScaleStiffness(const FabricMaterial& m, double factor);

/// Particles of the row i_u = const (a weft line), ordered along v.
std::vector<int> WarpRow(const FabricModel& model, int i_u);

/// Steps until every speed is below `speed_tol_m_per_s` for 5 consecutive steps, or max_steps.
/// Returns the steps taken.
int RunToRest(FabricStepper* stepper, FabricState* state, int max_steps, double speed_tol_m_per_s);

/// Elongation under a hanging load: exact integral of the inverse tensile curve along the strip.
/// L rest length, b width, rho areal density, load P at the bottom, gravity g.
double AnalyticHangingElongation(const StrainCurve& curve, double length_m, double width_m, double rho_kg_per_m2,
                                 double load_N, double g_m_per_s2);

/// Random deformation of the rest state (seeded: the same every run), with random velocities:
/// each coordinate moves by up to dx_m, each velocity is up to dv_m_per_s.
void Perturb(FabricState* s, double dx_m, double dv_m_per_s, unsigned seed);

}  // namespace haptex::textile::validation
