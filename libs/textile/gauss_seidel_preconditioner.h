#pragma once
// Symmetric (block) Gauss-Seidel / SSOR preconditioning of the implicit system with Eisenstat's
// trick (Eisenstat 1981; Saad, "Iterative Methods for Sparse Linear Systems", section 9.2).
//
// With A = L + D + U (U = L^T) and D_w = D / omega, SSOR's preconditioner is
// M = (D_w + L) D_w^-1 (D_w + U). CG runs on the split system
//   A~ = (D_w + L)^-1 A (D_w + U)^-1,  preconditioned by D_w,
// and A~ c = t + (D_w + L)^-1 (c - (2 D_w - D) t) with t = (D_w + U)^-1 c: one backward and one
// forward triangular sweep over the off-diagonal blocks per iteration, the cost of about one
// product with A. On the tension-dominated grids of a fine patch it needs far fewer iterations
// than block Jacobi. The filter: rows that are not free take no part (their values stay 0).

#include <vector>

#include <Eigen/Core>

#include "libs/textile/block_pattern.h"

namespace haptex::textile {

namespace internal {
/// A 3x3 block with each column padded to 4 doubles (the 4th is 0): one aligned 4-wide load
/// per column.
struct PaddedBlock {
  alignas(32) double col[3][4] = {};
  void Set(const Eigen::Matrix3d& m) {
    for (int j = 0; j < 3; ++j) {
      for (int i = 0; i < 3; ++i) col[j][i] = m(i, j);
      col[j][3] = 0.0;
    }
  }
  void SetZero() {
    for (auto& c : col) c[0] = c[1] = c[2] = c[3] = 0.0;
  }
};

/// What one triangular sweep reads (gauss_seidel_preconditioner.cc).
struct GaussSeidelSweepArgs {
  const SplitRows* split;
  const int* general_diag;
  const int* scalar_upper;
  const unsigned char* adjacent_lower;
  const unsigned char* adjacent_upper;
  const PaddedBlock* diag;
  const PaddedBlock* diag_inv;
  const PaddedBlock* adjacent_lower_scaled;
  const PaddedBlock* adjacent_upper_scaled;
  const Eigen::Matrix3d* blocks;
  const double* scalars;
  int rows;
  double diag_excess;
  bool avx2;  ///< the AVX2 kernel (else the portable one: same results)
};
}  // namespace internal

class GaussSeidelPreconditioner {
 public:
  GaussSeidelPreconditioner() = default;
  /// Records where each row's blocks switch from below to above the diagonal in `split`
  /// (each row's general and scalar columns sorted). Allocates; call once per model. The other
  /// calls take the same `split` (and blocks in its pattern's slot order, scalars in its order).
  explicit GaussSeidelPreconditioner(const SplitRows& split);

  /// Inverts the (scaled) diagonal blocks of `blocks` for relaxation factor omega in (0, 2).
  /// Returns false if a free row's diagonal block is not invertible. Never allocates.
  template <typename RowFree>
  bool Update(const SplitRows& split, const BlockPattern& pattern,
              const std::vector<Eigen::Matrix3d>& blocks, double omega, RowFree row_free);

  /// y = (D_w + L)^-1 x over the free rows (0 elsewhere; x must be 0 there). Never allocates.
  void ForwardSolve(const SplitRows& split, const std::vector<Eigen::Matrix3d>& blocks, const std::vector<double>& scalars,
                    const Eigen::VectorXd& x, Eigen::VectorXd* y) const;
  /// y = (D_w + U)^-1 x over the free rows (0 elsewhere; x must be 0 there). Never allocates.
  void BackwardSolve(const SplitRows& split, const std::vector<Eigen::Matrix3d>& blocks, const std::vector<double>& scalars,
                     const Eigen::VectorXd& x, Eigen::VectorXd* y) const;
  /// y = A~ x with A~ = (D_w + L)^-1 A (D_w + U)^-1; `t` and `z` are scratch. Returns x . y.
  double MultiplySplit(const SplitRows& split, const std::vector<Eigen::Matrix3d>& blocks, const std::vector<double>& scalars,
                       const Eigen::VectorXd& x, Eigen::VectorXd* t, Eigen::VectorXd* z,
                       Eigen::VectorXd* y) const;
  /// y = D_w x over the free rows (CG's preconditioner on A~); returns x . y. Never allocates.
  double MultiplyDiagonal(const Eigen::VectorXd& x, Eigen::VectorXd* y) const;

  /// The sweeps use an AVX2 kernel where the CPU has it (checked at run time), else a portable
  /// one doing the same operations in the same order: identical results. This picks the
  /// portable one anyway (tests compare the two).
  void UsePortableKernel() { avx2_ = false; }
  /// Rows it was built for (0: default-constructed).
  int rows() const { return static_cast<int>(general_diag_.size()); }
  bool uses_avx2() const { return avx2_; }

 private:
  std::vector<int> general_diag_;  ///< per row: index (into general_col) of its diagonal block
  std::vector<int> scalar_upper_;  ///< per row: first scalar index above the diagonal
  internal::GaussSeidelSweepArgs Args(const SplitRows& split, const std::vector<Eigen::Matrix3d>& blocks,
                        const std::vector<double>& scalars) const;

  /// Per row: 1 if it couples to row r - 1 (r + 1) through a general block.
  std::vector<unsigned char> adjacent_lower_, adjacent_upper_;
  std::vector<internal::PaddedBlock> diag_;      ///< D_w per row (zero for rows that are not free)
  /// D_w^-1 A(r, r - 1) and D_w^-1 A(r, r + 1) where those blocks exist (zero elsewhere, and
  /// for rows or neighbours that are not free).
  std::vector<internal::PaddedBlock> adjacent_lower_scaled_, adjacent_upper_scaled_;
  std::vector<internal::PaddedBlock> diag_inv_;  ///< D_w^-1 per row (zero for rows that are not free)
  double omega_ = 1.0;
  bool avx2_ = false;
  double diag_excess_ = 0.0;               ///< (2 D_w - D) = diag_excess_ D_w: 2 - omega

  template <typename RowFree>
  bool UpdateRow(const SplitRows& split, const BlockPattern& pattern,
                 const std::vector<Eigen::Matrix3d>& blocks, int r, RowFree row_free);
};

template <typename RowFree>
bool GaussSeidelPreconditioner::Update(const SplitRows& split, const BlockPattern& pattern,
                                       const std::vector<Eigen::Matrix3d>& blocks, double omega,
                                       RowFree row_free) {
  omega_ = omega;
  diag_excess_ = 2.0 - omega;
  bool ok = true;
  for (int r = 0; r < pattern.rows(); ++r) ok = UpdateRow(split, pattern, blocks, r, row_free) && ok;
  return ok;
}

template <typename RowFree>
bool GaussSeidelPreconditioner::UpdateRow(const SplitRows& split, const BlockPattern& pattern,
                                          const std::vector<Eigen::Matrix3d>& blocks, int r,
                                          RowFree row_free) {
  const auto row = static_cast<std::size_t>(r);
  const bool lower = adjacent_lower_[row] && row_free(r) && row_free(r - 1);
  const bool upper = adjacent_upper_[row] && row_free(r) && row_free(r + 1);
  if (!lower) adjacent_lower_scaled_[row].SetZero();
  if (!upper) adjacent_upper_scaled_[row].SetZero();
  if (!row_free(r)) {
    diag_[row].SetZero();
    diag_inv_[row].SetZero();
    return true;
  }
  const Eigen::Matrix3d d = blocks[static_cast<std::size_t>(pattern.diag_slot[row])] / omega_;
  Eigen::Matrix3d d_inv;
  bool invertible = false;
  double det = 0.0;
  d.computeInverseAndDetWithCheck(d_inv, det, invertible, 0.0);
  if (!invertible || !d_inv.allFinite()) {
    diag_[row].SetZero();
    diag_inv_[row].SetZero();
    adjacent_lower_scaled_[row].SetZero();
    adjacent_upper_scaled_[row].SetZero();
    return false;
  }
  diag_[row].Set(d);
  diag_inv_[row].Set(d_inv);
  // Slot of general index k: general_first_slot[r] + (k - general_start[r]).
  const int first = split.general_first_slot[row] - split.general_start[row];
  if (lower) {
    adjacent_lower_scaled_[row].Set(d_inv * blocks[static_cast<std::size_t>(first + general_diag_[row] - 1)]);
  }
  if (upper) {
    adjacent_upper_scaled_[row].Set(d_inv * blocks[static_cast<std::size_t>(first + general_diag_[row] + 1)]);
  }
  return true;
}

}  // namespace haptex::textile
