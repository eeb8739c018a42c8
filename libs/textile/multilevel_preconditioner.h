#pragma once
// Geometric multigrid used as a CG preconditioner: every second grid node along each direction
// is a node of the next level, the others are interpolated bilinearly from their coarse
// neighbours (a piecewise-constant prolongation, 2 x 2 aggregation, took about twice the CG
// iterations), coarse matrices are Galerkin products P^T A P, damped block-Jacobi smoothing, a
// dense Cholesky solve on the coarsest level. The finest level
// is additive (z = D^-1 r + P B_c P^T r: no product with the fine matrix), the coarser levels form
// a symmetric V-cycle; both keep B symmetric positive definite.
// Constrained particles are filtered out at the finest level. Built once; Update/Apply never
// allocate.

#include <vector>

#include <Eigen/Core>

#include "libs/textile/block_pattern.h"
#include "libs/textile/fabric_model.h"
#include "libs/textile/fabric_state.h"

namespace haptex::textile {

class MultilevelPreconditioner {
 public:
  explicit MultilevelPreconditioner(const FabricModel& model);

  /// Rebuilds the hierarchy for system blocks `a` (model.pattern) and the state's constraints.
  void Update(const FabricModel& model, const FabricState& state, const std::vector<Eigen::Matrix3d>& a);
  /// z = B r, an SPD approximation of A^-1 (z = 0 at constrained particles).
  void Apply(const Eigen::VectorXd& r, Eigen::VectorXd* z);

  int num_levels() const { return static_cast<int>(levels_.size()); }

 private:
  struct Level {
    int n = 0;                           // nodes
    BlockPattern own_pattern;            // coarse levels (level 0 uses the model's)
    std::vector<Eigen::Matrix3d> a;      // coarse levels (level 0 uses the system passed to Update)
    std::vector<Eigen::Matrix3d> d_inv;  // damped inverse diagonal (0 where filtered)
    // Prolongation to this level from the next (empty on the coarsest): node p takes weight
    // p_weight[e] of next-level node p_coarse[e], e in [p_start[p], p_start[p + 1]).
    std::vector<int> p_start, p_coarse;
    std::vector<double> p_weight;
    // Galerkin product: block slot k adds g_weight[e] times itself to next-level slot g_slot[e],
    // e in [g_start[k], g_start[k + 1]), for the next level's blocks on or above the diagonal;
    // the next level copies the others as transposes (mirror_slot).
    std::vector<int> g_start, g_slot;
    std::vector<double> g_weight;
    // Blocks that only bending makes (a scalar times the identity, never diagonal): scalar[slot].
    // On coarse levels they sit at the end of each row and the products read them as one value
    // each (split, scalars: as CG's product of the finest level, MultiplySplitRows).
    std::vector<unsigned char> scalar;
    SplitRows split;
    std::vector<double> scalars;
    Eigen::VectorXd az;                 // A z of a coarse level
    std::vector<int> mirror_slot;       // coarse levels: slot of block (c, r) for block (r, c), r > c; else -1
    std::vector<unsigned char> active;  // level 0: free particle
    Eigen::VectorXd r, z, t;
  };

  const BlockPattern& Pattern(std::size_t k) const { return k == 0 ? *fine_pattern_ : levels_[k].own_pattern; }
  const std::vector<Eigen::Matrix3d>& Blocks(std::size_t k) const { return k == 0 ? *fine_blocks_ : levels_[k].a; }
  Eigen::Vector3d Residual(std::size_t k, int p) const;
  void MultiplyCoarse(std::size_t k);
  void Smooth(std::size_t k);
  void RestrictResidual(std::size_t k);
  void Prolong(std::size_t k, Eigen::VectorXd* z) const;
  void Cycle(std::size_t k);

  const BlockPattern* fine_pattern_ = nullptr;                 // the model's (outlives this)
  const std::vector<Eigen::Matrix3d>* fine_blocks_ = nullptr;  // set by Update
  std::vector<Level> levels_;
  Eigen::MatrixXd dense_;  // coarsest matrix, then its Cholesky factor
  Eigen::VectorXd dense_rhs_;
  double omega_ = 0.6;  // Jacobi damping, lowered per level when a bound requires it
};

}  // namespace haptex::textile
