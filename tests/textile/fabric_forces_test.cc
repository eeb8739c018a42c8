#include "libs/textile/fabric_forces.h"

#include <cmath>
#include <cstring>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "libs/base/cpu_features.h"
#include "libs/textile/bending_force.h"
#include "libs/textile/drag_force.h"
#include "libs/textile/external_force.h"
#include "libs/textile/kes_material.h"
#include "libs/textile/shear_force.h"
#include "libs/textile/tensile_force.h"
#include "tests/textile/force_jacobian_check.h"

namespace haptex::textile {
namespace {

struct Assembled {
  Eigen::VectorXd f, dfdx_v;
  std::vector<Eigen::Matrix3d> system;
};

Assembled Empty(const FabricModel& model) {
  Assembled a;
  a.f = Eigen::VectorXd::Zero(3 * model.num_particles);
  a.dfdx_v = a.f;
  a.system.assign(static_cast<std::size_t>(model.pattern.num_blocks()), Eigen::Matrix3d::Zero());
  return a;
}

ForceSink SinkFor(Assembled* a, const FabricState& s) {
  ForceSink sink;
  sink.force_N = &a->f;
  sink.system = &a->system;
  sink.dx_scale = -1e-4;
  sink.dv_scale = -1e-2;
  sink.dfdx_v = &a->dfdx_v;
  sink.v = &s.v_W_m_per_s;
  return sink;
}

// The sum of the reference per-force functions at the state.
Assembled Reference(const FabricModel& model, const FabricState& s) {
  Assembled ref = Empty(model);
  ForceSink rs = SinkFor(&ref, s);
  AddTensileForces(model, s.x_W_m, s.v_W_m_per_s, &rs);
  AddShearForces(model, s.x_W_m, s.v_W_m_per_s, &rs);
  AddBendingForces(model, s.x_W_m, s.v_W_m_per_s, &rs);
  AddDragForces(model, s.x_W_m, s.v_W_m_per_s, &rs);
  AddExternalForces(model, s, &rs);
  return ref;
}

double MaxAbs(const std::vector<Eigen::Matrix3d>& blocks) {
  double m = 0.0;
  for (const auto& b : blocks) m = std::max(m, b.cwiseAbs().maxCoeff());
  return m;
}

// The fused one-pass assembly against the sum of the reference per-force functions, in tension,
// compression (a crumpled, moving state) and with the constant blocks cached.
TEST(FabricForcesTest, FusedAssemblyEqualsSumOfForces) {
  const FabricModel model = BuildFabricModel(MaterialFromKes(testing::CompositeDenim()), {0.05, 0.04, 6, 5});
  for (const double stretch : {1.02, 0.97}) {
    FabricState s = MakeRestState(model);
    for (int p = 0; p < model.num_particles; ++p) {
      s.x(p) = s.x(p).cwiseProduct(Eigen::Vector3d(stretch, 1.0 + 0.5 * (stretch - 1.0), 1.0));
    }
    testing::Perturb(&s, 2e-3, 0.3, 11);
    SetPointLoad(3, Eigen::Vector3d(0.1, -0.2, 0.3), &s);

    const Assembled ref = Reference(model, s);

    Assembled fused = Empty(model);
    ForceSink fs = SinkFor(&fused, s);
    AccumulateForces(model, s, &fs);

    Assembled cached = Empty(model);
    ForceSink cs = SinkFor(&cached, s);
    AddConstantJacobians(model, &cs);
    cs.constant_jacobians_added = true;
    AccumulateForces(model, s, &cs);

    const double f_tol = 1e-12 * ref.f.cwiseAbs().maxCoeff();
    const double v_tol = 1e-12 * ref.dfdx_v.cwiseAbs().maxCoeff();
    const double a_tol = 1e-12 * MaxAbs(ref.system);
    for (const Assembled* a : {&fused, &cached}) {
      EXPECT_LE((a->f - ref.f).cwiseAbs().maxCoeff(), f_tol) << "stretch " << stretch;
      EXPECT_LE((a->dfdx_v - ref.dfdx_v).cwiseAbs().maxCoeff(), v_tol) << "stretch " << stretch;
      for (std::size_t k = 0; k < ref.system.size(); ++k) {
        EXPECT_LE((a->system[k] - ref.system[k]).cwiseAbs().maxCoeff(), a_tol) << "block " << k;
      }
    }

    // Forces only: the same force vector.
    Eigen::VectorXd f_only = Eigen::VectorXd::Zero(3 * model.num_particles);
    ForceSink os;
    os.force_N = &f_only;
    AccumulateForces(model, s, &os);
    EXPECT_LE((f_only - ref.f).cwiseAbs().maxCoeff(), f_tol);
  }
}

// The fused assembly against the reference per-force functions for one state.
void ExpectFusedEqualsReference(const FabricModel& model, const FabricState& s, const char* what) {
  const Assembled ref = Reference(model, s);
  Assembled fused = Empty(model);
  ForceSink fs = SinkFor(&fused, s);
  AccumulateForces(model, s, &fs);
  EXPECT_LE((fused.f - ref.f).cwiseAbs().maxCoeff(), 1e-12 * ref.f.cwiseAbs().maxCoeff()) << what;
  EXPECT_LE((fused.dfdx_v - ref.dfdx_v).cwiseAbs().maxCoeff(), 1e-12 * ref.dfdx_v.cwiseAbs().maxCoeff()) << what;
  const double a_tol = 1e-12 * MaxAbs(ref.system);
  for (std::size_t k = 0; k < ref.system.size(); ++k) {
    EXPECT_LE((fused.system[k] - ref.system[k]).cwiseAbs().maxCoeff(), a_tol) << what << ", block " << k;
  }
  Eigen::VectorXd f_only = Eigen::VectorXd::Zero(3 * model.num_particles);
  ForceSink os;
  os.force_N = &f_only;
  AccumulateForces(model, s, &os);
  EXPECT_LE((f_only - ref.f).cwiseAbs().maxCoeff(), 1e-12 * ref.f.cwiseAbs().maxCoeff()) << what;
}

// The kernel takes triangles four at a time: a count that is not a multiple of four (a 4x4 grid
// has 18), a collapsed quad (both its triangles have coincident corners: no tensile force, no
// drag) and a patch without quadratic drag must still match the reference.
// A material angle changes only the triangles' weights: the fused kernel still matches.
TEST(FabricForcesTest, FusedAssemblyEqualsSumOfForcesOnTheBias) {
  ModelOptions options;
  options.material_angle_rad = 0.6;
  const FabricModel model = BuildFabricModel(MaterialFromKes(testing::CompositeDenim()), {0.05, 0.04, 6, 5}, options);
  FabricState s = MakeRestState(model);
  for (int p = 0; p < model.num_particles; ++p) s.x(p) = s.x(p).cwiseProduct(Eigen::Vector3d(1.02, 0.99, 1.0));
  testing::Perturb(&s, 2e-3, 0.3, 12);
  ExpectFusedEqualsReference(model, s, "material angle 0.6 rad");
}

TEST(FabricForcesTest, FusedAssemblyHandlesTailCollapsedElementsAndNoDrag) {
  for (const double drag_coefficient : {1.5, 0.0}) {
    ModelOptions options;
    options.drag.quadratic_coefficient = drag_coefficient;
    const FabricModel model = BuildFabricModel(MaterialFromKes(testing::CompositeDenim()), {0.03, 0.03, 4, 4}, options);
    ASSERT_NE(model.triangles.size() % 4, 0u);
    FabricState s = MakeRestState(model);
    for (int p = 0; p < model.num_particles; ++p) {
      s.x(p) = s.x(p).cwiseProduct(Eigen::Vector3d(1.02, 0.99, 1.0));
    }
    testing::Perturb(&s, 1e-3, 0.3, 5);
    ExpectFusedEqualsReference(model, s, drag_coefficient > 0.0 ? "drag" : "no drag");

    // Collapse the first quad (corners 0, 1, nu, nu + 1) onto particle 0.
    const int nu = model.mesh.particles_warp();
    for (const int p : {1, nu, nu + 1}) s.x(p) = s.x(0);
    ExpectFusedEqualsReference(model, s, drag_coefficient > 0.0 ? "collapsed, drag" : "collapsed, no drag");
  }
}

// The builds this CPU runs, vector ones first.
std::vector<internal::ForceKernels> VectorKernels() {
  std::vector<internal::ForceKernels> kernels;
  if (base::CpuHasAvx2()) kernels.push_back(internal::ForceKernels::kAvx2);
  if (base::CpuHasAvx2() && base::CpuHasAvx512Vl()) {
    kernels.push_back(internal::ForceKernels::kAvx2On32Registers);
  }
  return kernels;
}

// The AVX2 kernels (on 16 and, where the CPU has AVX-512VL, 32 registers) and their portable
// build give the same bits, with a tail group, a collapsed quad, with and without quadratic drag.
TEST(FabricForcesTest, Avx2AndPortableKernelsGiveTheSameBits) {
  if (!base::CpuHasAvx2()) GTEST_SKIP() << "no AVX2 on this CPU";
  const auto same_bits = [](const auto& a, const auto& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof a[0]) == 0;
  };
  for (const double drag_coefficient : {1.5, 0.0}) {
    ModelOptions options;
    options.drag.quadratic_coefficient = drag_coefficient;
    const FabricModel model = BuildFabricModel(MaterialFromKes(testing::CompositeDenim()), {0.03, 0.03, 6, 6}, options);
    ASSERT_NE(model.triangles.size() % 4, 0u);
    for (const double stretch : {1.02, 0.97}) {
      FabricState s = MakeRestState(model);
      for (int p = 0; p < model.num_particles; ++p) {
        s.x(p) = s.x(p).cwiseProduct(Eigen::Vector3d(stretch, 1.0 + 0.5 * (stretch - 1.0), 1.0));
      }
      testing::Perturb(&s, 2e-3, 0.3, 7);
      const int nu = model.mesh.particles_warp();
      for (const int p : {1, nu, nu + 1}) s.x(p) = s.x(0);
      Assembled portable = Empty(model);
      ForceSink ps = SinkFor(&portable, s);
      internal::AccumulateForces(model, s, internal::ForceKernels::kPortable, &ps);
      for (const internal::ForceKernels kernels : VectorKernels()) {
        Assembled avx2 = Empty(model);
        ForceSink as = SinkFor(&avx2, s);
        internal::AccumulateForces(model, s, kernels, &as);
        const int build = static_cast<int>(kernels);
        EXPECT_TRUE(same_bits(portable.f, avx2.f)) << "stretch " << stretch << " build " << build;
        EXPECT_TRUE(same_bits(portable.dfdx_v, avx2.dfdx_v)) << "stretch " << stretch << " build " << build;
        EXPECT_TRUE(same_bits(portable.system, avx2.system)) << "stretch " << stretch << " build " << build;
      }
    }
  }
}

// With sink.system_base the triangle kernel starts each block it touches from the base (its
// first addition per FabricModel::triangle_first_blocks) instead of the system's block: the
// same bits as the base copied in and added to, whatever the blocks held (NaN here), in both
// builds; each touched slot has exactly one first addition.
void ExpectFirstAdditionsStartFromTheBase(const FabricModel& model, const char* what) {
  std::vector<int> firsts(static_cast<std::size_t>(model.pattern.num_blocks()), 0);
  for (std::size_t t = 0; t < model.triangles.size(); ++t) {
    for (std::size_t kl = 0; kl < 9; ++kl) {
      ASSERT_LE(model.triangle_first_blocks[t][kl], 1) << what;  // indexes {system, base}
      if (model.triangle_first_blocks[t][kl] == 1) ++firsts[static_cast<std::size_t>(model.triangle_slots[t][kl])];
    }
  }
  for (const auto& slots : model.triangle_slots) {
    for (int slot : slots) EXPECT_EQ(firsts[static_cast<std::size_t>(slot)], 1) << what << " slot " << slot;
  }
  EXPECT_TRUE(model.general_slots_without_triangles.empty()) << what;
  FabricState s = MakeRestState(model);
  testing::Perturb(&s, 2e-3, 0.3, 7);
  // A base with -0 and +0 entries: 0 + (-0) is +0, which the start from the base must keep.
  std::vector<Eigen::Matrix3d> base(static_cast<std::size_t>(model.pattern.num_blocks()));
  for (std::size_t k = 0; k < base.size(); ++k) {
    base[k] = (k % 3 == 0 ? -0.0 : 0.25 * static_cast<double>(k)) * Eigen::Matrix3d::Identity();
  }
  const auto same_bits = [](const auto& a, const auto& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof a[0]) == 0;
  };
  std::vector<internal::ForceKernels> builds = VectorKernels();
  builds.insert(builds.begin(), internal::ForceKernels::kPortable);
  for (const internal::ForceKernels kernels : builds) {
    const int build = static_cast<int>(kernels);
    Assembled added = Empty(model), started = Empty(model);
    added.system = base;
    started.system.assign(base.size(), Eigen::Matrix3d::Constant(std::nan("")));
    ForceSink as = SinkFor(&added, s), ss = SinkFor(&started, s);
    ss.system_base = base.data();
    internal::AccumulateForces(model, s, kernels, &as);
    internal::AccumulateForces(model, s, kernels, &ss);
    EXPECT_TRUE(same_bits(added.f, started.f)) << what << " build " << build;
    EXPECT_TRUE(same_bits(added.dfdx_v, started.dfdx_v)) << what << " build " << build;
    for (std::size_t k = 0; k < base.size(); ++k) {
      if (firsts[k] == 0) continue;  // blocks no triangle touches: the caller's
      EXPECT_EQ(std::memcmp(added.system[k].data(), started.system[k].data(), sizeof(Eigen::Matrix3d)), 0)
          << what << " build " << build << " slot " << k;
    }
  }
}

TEST(FabricForcesTest, FirstAdditionsStartFromTheBase) {
  FabricModel model = BuildFabricModel(MaterialFromKes(testing::CompositeDenim()), {0.03, 0.03, 6, 6});
  ASSERT_NE(model.triangles.size() % 4, 0u);  // a tail group
  ExpectFirstAdditionsStartFromTheBase(model, "grid");
  // Corners 0 and 1 of every other triangle swapped (the same element): a quad's two triangles
  // then reach their new shared slot as blocks 2 and 3, so the kernel's block order decides
  // which addition is first (in the grid's own order either order gives the same).
  for (std::size_t t = 1; t < model.triangles.size(); t += 2) {
    TriangleElement& e = model.triangles[t];
    std::swap(e.p[0], e.p[1]);
    std::swap(e.a[0], e.a[1]);
    std::swap(e.b[0], e.b[1]);
    for (std::size_t kl = 0; kl < 9; ++kl) {
      const int slot = model.pattern.Slot(e.p[kl / 3], e.p[kl % 3]);
      model.triangle_slots[t][kl] = slot;
      model.triangle_block_offsets[t][kl] = slot * static_cast<int>(sizeof(Eigen::Matrix3d));
    }
  }
  model.triangle_first_blocks = internal::TriangleFirstBlocks(model.triangle_slots, model.pattern.num_blocks());
  ExpectFirstAdditionsStartFromTheBase(model, "swapped");
}

}  // namespace
}  // namespace haptex::textile
