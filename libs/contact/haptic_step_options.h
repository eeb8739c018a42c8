#pragma once
// The fabric step of a haptic tick: what local_contact runs on its patch, every tick.

#include "libs/textile/step_options.h"

namespace haptex::contact {

/// Implicit Euler with symmetric Gauss-Seidel (SSOR, omega 1.6) PCG, warm-started, to 1e-2 or
/// at most 6 iterations. Chosen by bench/contact/contact_tick_bench (BM_*Accuracy against a
/// solve to 1e-9): finger forces closer to the tight solve than block Jacobi's 20 iterations,
/// in less time per tick; fewer iterations were less accurate, and 2 went unstable. Omega 1.6
/// gave the smallest pinch error of 1.4-1.9 at the same iterations (1.7 and 1.8 were slightly
/// better for one finger, worse for the pinch); 1.9 went unstable at a cap of 4.
textile::StepOptions HapticPatchStepOptions(double dt_s);

}  // namespace haptex::contact
