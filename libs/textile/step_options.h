#pragma once
// Integrator choice and its accuracy/speed dials: inputs, never constants.

namespace haptex::textile {

enum class Integrator {
  kImplicitEuler,    ///< Baraff-Witkin: one Newton step, filtered PCG (default, unconditionally stable)
  kSymplecticEuler,  ///< semi-implicit (symplectic) Euler with substeps: cheap, conditionally stable
};

/// CG preconditioner of the implicit integrator.
enum class Preconditioner {
  kBlockJacobi,  ///< inverse 3x3 diagonal blocks: cheapest per iteration
  kMultilevel,   ///< aggregation multigrid V-cycle: far fewer iterations on fine, stiff meshes
  /// symmetric Gauss-Seidel / SSOR with Eisenstat's trick: about one product per iteration, far
  /// fewer iterations than block Jacobi on small stiff patches, no set-up beyond the diagonal
  kGaussSeidel,
};

struct StepOptions {
  Integrator method = Integrator::kImplicitEuler;
  double dt_s = 0.01;           ///< step [s], > 0
  double cg_tolerance = 1e-2;   ///< relative preconditioned residual, in (0, 1)
  int cg_max_iterations = 200;  ///< >= 1
  /// Start CG from the previous step's velocity change (else from zero). Results then depend on
  /// the workspace's history within the CG tolerance.
  bool cg_warm_start = true;
  Preconditioner preconditioner = Preconditioner::kMultilevel;
  /// kGaussSeidel's relaxation factor omega in (0, 2): 1 is symmetric Gauss-Seidel.
  double ssor_omega = 1.0;
  /// Symplectic substeps per step; 0 = the fewest that the stability estimate allows.
  int substeps = 0;
  int max_substeps = 2000;           ///< refuse configurations needing more
  double max_speed_m_per_s = 100.0;  ///< particle speeds above are clamped and counted
};

/// @throws std::invalid_argument naming the option (dt_s <= 0, tolerance outside (0, 1), ...).
void ValidateStepOptions(const StepOptions& options);

}  // namespace haptex::textile
