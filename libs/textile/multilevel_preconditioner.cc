#include "libs/textile/multilevel_preconditioner.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <Eigen/Dense>

#include "libs/base/demand.h"

namespace haptex::textile {
namespace {

constexpr int kCoarsestNodes = 32;  // stop coarsening at or below this many nodes

// Fine node i of a line of n takes these next-level nodes (every second fine node) and weights:
// itself if even, else the mean of its two even neighbours (the last one alone at an end).
int CoarseLine(int i, int n, int coarse[2], double weight[2]) {
  if (i % 2 == 0) {
    coarse[0] = i / 2;
    weight[0] = 1.0;
    return 1;
  }
  coarse[0] = (i - 1) / 2;
  if (i + 1 >= n) {
    weight[0] = 1.0;
    return 1;
  }
  coarse[1] = (i + 1) / 2;
  weight[0] = weight[1] = 0.5;
  return 2;
}

}  // namespace

MultilevelPreconditioner::MultilevelPreconditioner(const FabricModel& model) {
  int nu = model.mesh.particles_warp(), nv = model.mesh.particles_weft();
  levels_.emplace_back();
  levels_[0].n = model.num_particles;
  fine_pattern_ = &model.pattern;
  levels_[0].active.assign(static_cast<std::size_t>(model.num_particles), 1);
  levels_[0].scalar.assign(model.pattern.cols.size(), 0);
  for (int slot : model.product_rows.scalar_slot) levels_[0].scalar[static_cast<std::size_t>(slot)] = 1;
  while (levels_.back().n > kCoarsestNodes && (nu > 1 || nv > 1)) {
    const int cu = (nu + 1) / 2, cv = (nv + 1) / 2;
    Level& fine = levels_.back();
    fine.p_start.assign(1, 0);
    for (int j = 0; j < nv; ++j) {
      int cj[2], ci[2];
      double wj[2], wi[2];
      const int mj = CoarseLine(j, nv, cj, wj);
      for (int i = 0; i < nu; ++i) {
        const int mi = CoarseLine(i, nu, ci, wi);
        for (int b = 0; b < mj; ++b) {
          for (int a = 0; a < mi; ++a) {
            fine.p_coarse.push_back(ci[a] + cu * cj[b]);
            fine.p_weight.push_back(wi[a] * wj[b]);
          }
        }
        fine.p_start.push_back(static_cast<int>(fine.p_coarse.size()));
      }
    }
    const BlockPattern& fp = Pattern(levels_.size() - 1);
    auto each_coarse_pair = [&](auto&& visit) {
      for (int r = 0; r < fine.n; ++r) {
        for (int k = fp.row_start[static_cast<std::size_t>(r)]; k < fp.row_start[static_cast<std::size_t>(r) + 1];
             ++k) {
          const int c = fp.cols[static_cast<std::size_t>(k)];
          for (int ea = fine.p_start[static_cast<std::size_t>(r)]; ea < fine.p_start[static_cast<std::size_t>(r) + 1];
               ++ea) {
            for (int eb = fine.p_start[static_cast<std::size_t>(c)]; eb < fine.p_start[static_cast<std::size_t>(c) + 1];
                 ++eb) {
              visit(k, fine.p_coarse[static_cast<std::size_t>(ea)], fine.p_coarse[static_cast<std::size_t>(eb)],
                    fine.p_weight[static_cast<std::size_t>(ea)] * fine.p_weight[static_cast<std::size_t>(eb)]);
            }
          }
        }
      }
    };
    std::vector<std::pair<int, int>> pairs;
    each_coarse_pair([&](int, int a, int b, double) {
      if (a != b) pairs.emplace_back(a, b);
    });
    Level coarse;
    coarse.n = cu * cv;
    coarse.own_pattern = BlockPattern::FromPairs(coarse.n, pairs);
    // A coarse block is scalar when every fine block it sums is; those go to the row ends.
    auto mark_scalar = [&] {
      coarse.scalar.assign(coarse.own_pattern.cols.size(), 1);
      for (int slot : coarse.own_pattern.diag_slot) coarse.scalar[static_cast<std::size_t>(slot)] = 0;
      each_coarse_pair([&](int k, int a, int b, double) {
        if (!fine.scalar[static_cast<std::size_t>(k)]) {
          coarse.scalar[static_cast<std::size_t>(coarse.own_pattern.Slot(a, b))] = 0;
        }
      });
    };
    mark_scalar();
    coarse.own_pattern.MoveToRowEnds(coarse.scalar);
    mark_scalar();
    coarse.split = SplitRows::FromPattern(coarse.own_pattern, coarse.scalar);
    coarse.scalars.assign(coarse.split.scalar_slot.size(), 0.0);
    coarse.mirror_slot.assign(coarse.own_pattern.cols.size(), -1);
    for (int r = 0; r < coarse.n; ++r) {
      for (int k = coarse.own_pattern.row_start[static_cast<std::size_t>(r)];
           k < coarse.own_pattern.row_start[static_cast<std::size_t>(r) + 1]; ++k) {
        const int c = coarse.own_pattern.cols[static_cast<std::size_t>(k)];
        if (r > c) coarse.mirror_slot[static_cast<std::size_t>(k)] = coarse.own_pattern.Slot(c, r);
      }
    }
    fine.g_start.assign(fp.cols.size() + 1, 0);
    each_coarse_pair([&](int k, int a, int b, double) {
      if (a <= b) ++fine.g_start[static_cast<std::size_t>(k) + 1];
    });
    for (std::size_t k = 0; k < fp.cols.size(); ++k) fine.g_start[k + 1] += fine.g_start[k];
    fine.g_slot.resize(static_cast<std::size_t>(fine.g_start.back()));
    fine.g_weight.resize(fine.g_slot.size());
    std::vector<int> fill(fine.g_start.begin(), fine.g_start.end() - 1);
    each_coarse_pair([&](int k, int a, int b, double w) {
      if (a > b) return;
      const std::size_t e = static_cast<std::size_t>(fill[static_cast<std::size_t>(k)]++);
      fine.g_slot[e] = coarse.own_pattern.Slot(a, b);
      fine.g_weight[e] = w;
    });
    levels_.push_back(std::move(coarse));
    nu = cu;
    nv = cv;
  }
  for (std::size_t l = 0; l < levels_.size(); ++l) {
    Level& lev = levels_[l];
    if (l > 0) {
      lev.a.assign(lev.own_pattern.cols.size(), Eigen::Matrix3d::Zero());
      lev.active.assign(static_cast<std::size_t>(lev.n), 1);
    }
    lev.d_inv.assign(static_cast<std::size_t>(lev.n), Eigen::Matrix3d::Zero());
    lev.r = Eigen::VectorXd::Zero(3 * lev.n);
    lev.z = Eigen::VectorXd::Zero(3 * lev.n);
    lev.t = Eigen::VectorXd::Zero(3 * lev.n);
    if (l > 0) lev.az = Eigen::VectorXd::Zero(3 * lev.n);
  }
  dense_ = Eigen::MatrixXd::Zero(3 * levels_.back().n, 3 * levels_.back().n);
  dense_rhs_ = Eigen::VectorXd::Zero(3 * levels_.back().n);
}

void MultilevelPreconditioner::Update(const FabricModel& model, const FabricState& state,
                                      const std::vector<Eigen::Matrix3d>& a) {
  Level& top = levels_[0];
  fine_blocks_ = &a;
  for (int p = 0; p < model.num_particles; ++p) {
    top.active[static_cast<std::size_t>(p)] = state.mode[static_cast<std::size_t>(p)] == ParticleMode::kFree ? 1 : 0;
  }
  for (std::size_t l = 0; l < levels_.size(); ++l) {
    Level& lev = levels_[l];
    const BlockPattern& pat = Pattern(l);
    const std::vector<Eigen::Matrix3d>& blocks = Blocks(l);
    // Damped inverse diagonal (zero where filtered or where a whole aggregate is constrained).
    // If the damping is too strong for this matrix the V-cycle can lose positive definiteness;
    // the CG detects that and falls back to block Jacobi (implicit_euler.cc).
    for (int p = 0; p < lev.n; ++p) {
      const Eigen::Matrix3d& d = blocks[static_cast<std::size_t>(pat.diag_slot[static_cast<std::size_t>(p)])];
      Eigen::Matrix3d& d_inv = lev.d_inv[static_cast<std::size_t>(p)];
      if (!lev.active[static_cast<std::size_t>(p)] || !(d.trace() > 0.0)) {
        d_inv.setZero();
      } else {
        d_inv = omega_ * d.inverse();
      }
    }
    if (l + 1 == levels_.size()) break;
    // Galerkin coarse matrix P^T A P over the active fine rows and columns.
    Level& next = levels_[l + 1];
    for (auto& b : next.a) b.setZero();
    for (int r = 0; r < lev.n; ++r) {
      if (!lev.active[static_cast<std::size_t>(r)]) continue;
      for (int k = pat.row_start[static_cast<std::size_t>(r)]; k < pat.row_start[static_cast<std::size_t>(r) + 1];
           ++k) {
        if (!lev.active[static_cast<std::size_t>(pat.cols[static_cast<std::size_t>(k)])]) continue;
        const Eigen::Matrix3d& block = blocks[static_cast<std::size_t>(k)];
        for (int e = lev.g_start[static_cast<std::size_t>(k)]; e < lev.g_start[static_cast<std::size_t>(k) + 1]; ++e) {
          next.a[static_cast<std::size_t>(lev.g_slot[static_cast<std::size_t>(e)])] +=
              lev.g_weight[static_cast<std::size_t>(e)] * block;
        }
      }
    }
    for (std::size_t k = 0; k < next.a.size(); ++k) {
      const int mirror = next.mirror_slot[k];
      if (mirror >= 0) next.a[k] = next.a[static_cast<std::size_t>(mirror)].transpose();
    }
    for (std::size_t k = 0; k < next.scalars.size(); ++k) {
      next.scalars[k] = next.a[static_cast<std::size_t>(next.split.scalar_slot[k])](0, 0);
    }
    for (int p = 0; p < next.n; ++p) {
      Eigen::Matrix3d& d = next.a[static_cast<std::size_t>(next.own_pattern.diag_slot[static_cast<std::size_t>(p)])];
      next.active[static_cast<std::size_t>(p)] = d.trace() > 0.0 ? 1 : 0;
    }
  }
  // Coarsest level: dense Cholesky (identity rows for empty aggregates).
  const Level& last = levels_.back();
  const BlockPattern& last_pattern = Pattern(levels_.size() - 1);
  const std::vector<Eigen::Matrix3d>& last_blocks = Blocks(levels_.size() - 1);
  dense_.setZero();
  for (int r = 0; r < last.n; ++r) {
    if (!last.active[static_cast<std::size_t>(r)]) {
      dense_.block<3, 3>(3 * r, 3 * r).setIdentity();
      continue;
    }
    for (int k = last_pattern.row_start[static_cast<std::size_t>(r)];
         k < last_pattern.row_start[static_cast<std::size_t>(r) + 1]; ++k) {
      const int c = last_pattern.cols[static_cast<std::size_t>(k)];
      if (last.active[static_cast<std::size_t>(c)]) {
        dense_.block<3, 3>(3 * r, 3 * c) = last_blocks[static_cast<std::size_t>(k)];
      }
    }
  }
  // In-place lower Cholesky (no allocation).
  const Eigen::Index m = dense_.rows();
  for (Eigen::Index j = 0; j < m; ++j) {
    double d = dense_(j, j);
    for (Eigen::Index k = 0; k < j; ++k) d -= dense_(j, k) * dense_(j, k);
    d = d > 1e-300 ? std::sqrt(d) : 1.0;  // semi-definite fallback; CG still converges
    dense_(j, j) = d;
    for (Eigen::Index i = j + 1; i < m; ++i) {
      double s = dense_(i, j);
      for (Eigen::Index k = 0; k < j; ++k) s -= dense_(i, k) * dense_(j, k);
      dense_(i, j) = s / d;
    }
  }
}

namespace {

// Row p of the residual r - A z of the finest level (a single-level hierarchy only).
Eigen::Vector3d RowResidual(const Eigen::Matrix3d* blocks, const int* row_start, const int* cols, const double* z,
                            const double* r, int p) {
  double acc[3] = {0.0, 0.0, 0.0};
  AccumulateBlockRow(blocks, cols, row_start[p], row_start[p + 1], z, acc);
  return {r[3 * p] - acc[0], r[3 * p + 1] - acc[1], r[3 * p + 2] - acc[2]};
}

}  // namespace

// Row p of r - A z: from the coarse level's product az, or computed (finest level).
Eigen::Vector3d MultilevelPreconditioner::Residual(std::size_t level, int p) const {
  const Level& l = levels_[level];
  if (level > 0) return l.r.segment<3>(3 * p) - l.az.segment<3>(3 * p);
  const BlockPattern& pat = Pattern(level);
  return RowResidual(Blocks(level).data(), pat.row_start.data(), pat.cols.data(), l.z.data(), l.r.data(), p);
}

// Coarse levels: az = A z (the split product, as CG's).
void MultilevelPreconditioner::MultiplyCoarse(std::size_t level) {
  Level& l = levels_[level];
  if (level == 0) return;
  const unsigned char* active = l.active.data();
  MultiplySplitRows(
      l.split, l.a, l.scalars, [active](int row) { return active[row] != 0; }, l.z, &l.az);
}

// z += D^-1 (r - A z) (the new z goes to t, then z and t swap).
void MultilevelPreconditioner::Smooth(std::size_t level) {
  MultiplyCoarse(level);
  Level& l = levels_[level];
  const double* z = l.z.data();
  double* out = l.t.data();
  for (int p = 0; p < l.n; ++p) {
    const std::size_t ps = static_cast<std::size_t>(p);
    if (!l.active[ps]) {
      out[3 * p] = z[3 * p];
      out[3 * p + 1] = z[3 * p + 1];
      out[3 * p + 2] = z[3 * p + 2];
      continue;
    }
    Eigen::Map<Eigen::Vector3d>(out + 3 * p) = l.z.segment<3>(3 * p) + l.d_inv[ps] * Residual(level, p);
  }
  l.z.swap(l.t);
}

// Restricts the residual r - A z of level k to level k + 1 (c.r = P^T (r - A z)).
void MultilevelPreconditioner::RestrictResidual(std::size_t level) {
  MultiplyCoarse(level);
  const Level& l = levels_[level];
  Level& c = levels_[level + 1];
  double* cr = c.r.data();
  c.r.setZero();
  for (int p = 0; p < l.n; ++p) {
    const std::size_t ps = static_cast<std::size_t>(p);
    if (!l.active[ps]) continue;
    const Eigen::Vector3d res = Residual(level, p);
    for (int e = l.p_start[ps]; e < l.p_start[ps + 1]; ++e) {
      Eigen::Map<Eigen::Vector3d>(cr + 3 * l.p_coarse[static_cast<std::size_t>(e)]) +=
          l.p_weight[static_cast<std::size_t>(e)] * res;
    }
  }
}

void MultilevelPreconditioner::Cycle(std::size_t k) {
  Level& l = levels_[k];
  if (k + 1 == levels_.size()) {
    // Dense solve L L^T z = r.
    const Eigen::Index m = dense_.rows();
    for (Eigen::Index i = 0; i < m; ++i) {
      double s = l.r[i];
      for (Eigen::Index j = 0; j < i; ++j) s -= dense_(i, j) * dense_rhs_[j];
      dense_rhs_[i] = s / dense_(i, i);
    }
    for (Eigen::Index i = m - 1; i >= 0; --i) {
      double s = dense_rhs_[i];
      for (Eigen::Index j = i + 1; j < m; ++j) s -= dense_(j, i) * l.z[j];
      l.z[i] = s / dense_(i, i);
    }
    for (int p = 0; p < l.n; ++p) {
      if (!l.active[static_cast<std::size_t>(p)]) l.z.segment<3>(3 * p).setZero();
    }
    return;
  }
  // Symmetric V-cycle: Jacobi sweep from z = 0 (needs no product), restrict the residual,
  // coarse correction, one more Jacobi sweep.
  for (int p = 0; p < l.n; ++p) {
    l.z.segment<3>(3 * p).noalias() = l.d_inv[static_cast<std::size_t>(p)] * l.r.segment<3>(3 * p);
  }
  RestrictResidual(k);
  Cycle(k + 1);
  Prolong(k, &l.z);
  Smooth(k);
}

// z += P z_coarse at the active nodes.
void MultilevelPreconditioner::Prolong(std::size_t k, Eigen::VectorXd* z) const {
  const Level& l = levels_[k];
  const Level& c = levels_[k + 1];
  for (int p = 0; p < l.n; ++p) {
    const std::size_t ps = static_cast<std::size_t>(p);
    if (!l.active[ps]) continue;
    for (int e = l.p_start[ps]; e < l.p_start[ps + 1]; ++e) {
      z->segment<3>(3 * p) +=
          l.p_weight[static_cast<std::size_t>(e)] * c.z.segment<3>(3 * l.p_coarse[static_cast<std::size_t>(e)]);
    }
  }
}

void MultilevelPreconditioner::Apply(const Eigen::VectorXd& r, Eigen::VectorXd* z) {
  Level& top = levels_[0];
  if (levels_.size() == 1) {
    top.r = r;
    for (int p = 0; p < top.n; ++p) {
      if (!top.active[static_cast<std::size_t>(p)]) top.r.segment<3>(3 * p).setZero();
    }
    Cycle(0);
    *z = top.z;
    return;
  }
  // Finest level, additive: z = D^-1 r + P B_c P^T r, with B_c the V-cycle below. No product
  // with the fine matrix; CG needs about 1.7 times the iterations of a multiplicative finest
  // level, each far cheaper (d_inv is zero at filtered particles).
  Level& c = levels_[1];
  c.r.setZero();
  for (int p = 0; p < top.n; ++p) {
    z->segment<3>(3 * p).noalias() = top.d_inv[static_cast<std::size_t>(p)] * r.segment<3>(3 * p);
    const std::size_t ps = static_cast<std::size_t>(p);
    if (!top.active[ps]) continue;
    for (int e = top.p_start[ps]; e < top.p_start[ps + 1]; ++e) {
      c.r.segment<3>(3 * top.p_coarse[static_cast<std::size_t>(e)]) +=
          top.p_weight[static_cast<std::size_t>(e)] * r.segment<3>(3 * p);
    }
  }
  Cycle(1);
  Prolong(0, z);
}

}  // namespace haptex::textile
