#pragma once
// Integrator choice and its accuracy/speed dials: inputs, never constants.

namespace haptex::textile {

enum class Integrator {
  /// Baraff-Witkin: one Newton step, filtered PCG (first order; the default: it damps, and calms
  /// every cloth of the stability matrix at any step up to 33 ms)
  kImplicitEuler,
  kSymplecticEuler,  ///< semi-implicit (symplectic) Euler with substeps: cheap, conditionally stable
  /// Second-order backward differences: implicit Euler's solve (and its Newton iterations) on a
  /// step of 2/3 dt from the extrapolated (4 x_n - x_n-1) / 3, (4 v_n - v_n-1) / 3. Damps far
  /// less than implicit Euler (error O(dt^2); A-stable on a linear problem, fabric_stepper.h).
  /// Needs newton_max_iterations >= 2: with one linearised step it pumps energy into stiff
  /// crumpled cloths at 20 ms and longer and keeps a soft knit under a point load at the speed
  /// cap (docs/fabric-model.md, "Accuracy in motion"). With Newton it holds the stability matrix
  /// to 33 ms and keeps a moving cloth several times closer than implicit Euler, at several times
  /// its cost per step: not the default.
  kBdf2,
};

/// "implicit_euler", "symplectic_euler", "bdf2".
const char* IntegratorName(Integrator integrator);

/// CG preconditioner of the implicit integrator.
enum class Preconditioner {
  kBlockJacobi,  ///< inverse 3x3 diagonal blocks: cheapest per iteration
  kMultilevel,   ///< aggregation multigrid V-cycle: far fewer iterations on fine, stiff meshes
  /// symmetric Gauss-Seidel / SSOR with Eisenstat's trick: about one product per iteration, far
  /// fewer iterations than block Jacobi on small stiff patches, no set-up beyond the diagonal
  kGaussSeidel,
};

/// Deepest split of a step: 2^10 sub-steps is beyond any use and bounds a step's cost.
inline constexpr int kMaxStepHalvings = 10;

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

  // Implicit Euler's nonlinear solve. One iteration is Baraff-Witkin's single linearised step,
  // whose error in motion grows with the step (docs/fabric-model.md, "Accuracy in motion");
  // more iterate until the step's residual impulse |h f(x1, v1) - M (v1 - v0)| is below
  // newton_tolerance times the step's force level max(|h (f0 + h K v0)|, |h M g|), and CG then
  // solves only as precisely as that target needs (at most cg_tolerance, relative).
  int newton_max_iterations = 1;   ///< >= 1
  double newton_tolerance = 1e-2;  ///< in (0, 1)
  /// true: full Newton, reassembled each iteration; false: every iteration reuses the first
  /// one's matrix and preconditioner (a chord method: a forces-only pass per iteration), which
  /// diverges where the stiffness changes much within the step (elements going from compression
  /// to tension).
  bool newton_update_jacobian = true;
  /// A step whose Newton iterations do not converge, or whose largest tensile strain rises by
  /// more than max_strain_rise_per_step, is retaken as two halves, down to dt_s / 2^this; the
  /// rest of the step keeps the smaller step. 0: never split.
  ///
  /// The default bound is a guard, not an accuracy target: one linearised step of a stiffening
  /// law, linearised where the cloth is still soft, can stretch it 10-100 times further than it
  /// goes (a 1 N point load took denim to 2700 % strain, a converged step to 26 %), and no
  /// smooth motion raises the strain by 2 points in one step (docs/fabric-model.md, "The
  /// guard").
  int max_step_halvings = 3;
  double max_strain_rise_per_step = 0.02;  ///< [-]; 0: no strain bound
};

/// @throws std::invalid_argument naming the option (dt_s <= 0, tolerance outside (0, 1), ...).
void ValidateStepOptions(const StepOptions& options);

}  // namespace haptex::textile
