#include "libs/textile/fabric_model.h"

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>

#include <Eigen/Dense>

#include "libs/base/demand.h"
#include "libs/textile/fabric_forces.h"

namespace haptex::textile {
namespace {

void RequireNonNegative(const char* name, double value) {
  if (!std::isfinite(value) || value < 0.0) {
    throw std::invalid_argument(std::string("ModelOptions.") + name + " must be finite and >= 0 (got " +
                                std::to_string(value) + ")");
  }
}

void ValidateInputs(const FabricMaterial& m, const ModelOptions& o) {
  RequireNonNegative("damping.stretch_s", o.damping.stretch_s);
  RequireNonNegative("damping.shear_s", o.damping.shear_s);
  RequireNonNegative("damping.bend_s", o.damping.bend_s);
  RequireNonNegative("drag.linear_N_s_per_m3", o.drag.linear_N_s_per_m3);
  RequireNonNegative("drag.quadratic_coefficient", o.drag.quadratic_coefficient);
  RequireNonNegative("drag.air_density_kg_per_m3", o.drag.air_density_kg_per_m3);
  if (!std::isfinite(o.material_angle_rad)) {
    throw std::invalid_argument("ModelOptions.material_angle_rad must be finite");
  }
  if (!o.gravity_m_per_s2.allFinite()) {
    throw std::invalid_argument("ModelOptions.gravity_m_per_s2 must be finite");
  }
  if (!(std::isfinite(m.density_kg_per_m2) && m.density_kg_per_m2 > 0.0)) {
    throw std::invalid_argument("FabricMaterial.density_kg_per_m2 must be finite and > 0");
  }
  if (!(std::isfinite(m.bending_warp_Nm) && m.bending_warp_Nm >= 0.0 && std::isfinite(m.bending_weft_Nm) &&
        m.bending_weft_Nm >= 0.0)) {
    throw std::invalid_argument("FabricMaterial.bending_*_Nm must be finite and >= 0");
  }
  if (m.tensile_warp.loading().empty() || m.tensile_weft.loading().empty() || m.shear.loading().empty()) {
    throw std::invalid_argument("FabricMaterial: tensile and shear curves must be set");
  }
}

std::array<int, 9> Slots(const BlockPattern& pattern, const std::array<int, 3>& p) {
  std::array<int, 9> s{};
  for (int k = 0; k < 3; ++k) {
    for (int l = 0; l < 3; ++l) {
      s[static_cast<std::size_t>(k * 3 + l)] =
          pattern.Slot(p[static_cast<std::size_t>(k)], p[static_cast<std::size_t>(l)]);
    }
  }
  return s;
}

}  // namespace

FabricModel BuildFabricModel(const FabricMaterial& material, const GridSpec& grid, const ModelOptions& options) {
  ValidateInputs(material, options);
  FabricModel model{GridMesh(grid), material, options, 0, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}};
  const GridMesh& mesh = model.mesh;
  const int n = mesh.num_particles();
  model.num_particles = n;
  model.mass_kg = Eigen::VectorXd::Zero(n);
  model.area_m2 = Eigen::VectorXd::Zero(n);

  // Triangles: constant weights mapping positions to warp/weft vectors. The grid weights give
  // dx/du and dx/dv; the yarn vectors are their combinations along the warp (cos, sin) and the
  // weft (-sin, cos) in (u, v). Folding the angle into the weights here leaves every force kernel
  // as it is, and at angle 0 (cos 1, sin 0) the weights are exactly the grid's.
  const double cos_angle = std::cos(options.material_angle_rad);
  const double sin_angle = std::sin(options.material_angle_rad);
  for (const auto& t : mesh.triangles()) {
    const Eigen::Vector2d& q0 = mesh.rest_uv_m(t[0]);
    const Eigen::Vector2d& q1 = mesh.rest_uv_m(t[1]);
    const Eigen::Vector2d& q2 = mesh.rest_uv_m(t[2]);
    Eigen::Matrix2d d;
    d << q1.x() - q0.x(), q2.x() - q0.x(), q1.y() - q0.y(), q2.y() - q0.y();
    const Eigen::Matrix2d inv = d.inverse();
    TriangleElement e;
    e.p = t;
    const std::array<double, 3> grid_u{-inv(0, 0) - inv(1, 0), inv(0, 0), inv(1, 0)};
    const std::array<double, 3> grid_v{-inv(0, 1) - inv(1, 1), inv(0, 1), inv(1, 1)};
    for (std::size_t k = 0; k < 3; ++k) {
      e.a[k] = cos_angle * grid_u[k] + sin_angle * grid_v[k];
      e.b[k] = cos_angle * grid_v[k] - sin_angle * grid_u[k];
    }
    e.area_m2 = 0.5 * std::abs(d.determinant());
    for (int k : t) model.area_m2[k] += e.area_m2 / 3.0;
    model.triangles.push_back(e);
  }
  model.mass_kg = model.area_m2 * material.density_kg_per_m2;

  // Bending triplets along u lines (curvature along u) and v lines (curvature along v), each with
  // the rigidity of its direction, B_warp cos^2 phi + B_weft sin^2 phi at phi from the warp: u
  // lies at -angle from the warp, v at pi/2 - angle (cos and sin swap). Written with the angle's
  // own cos and sin so that 0 and pi/2 give the two rigidities exactly.
  const double cos2 = cos_angle * cos_angle, sin2 = sin_angle * sin_angle;
  const double bending_u_Nm = material.bending_warp_Nm * cos2 + material.bending_weft_Nm * sin2;
  const double bending_v_Nm = material.bending_warp_Nm * sin2 + material.bending_weft_Nm * cos2;
  const int nu = mesh.particles_warp(), nv = mesh.particles_weft();
  const double du = grid.length_warp_m / (nu - 1), dv = grid.width_weft_m / (nv - 1);
  auto add_line = [&](int p0, int p1, int p2, double l0, double l1, double width, double b) {
    BendElement e;
    e.p = {p0, p1, p2};
    e.alpha = {1.0 / l0, -(1.0 / l0 + 1.0 / l1), 1.0 / l1};
    e.lambda_N_per_m = 2.0 * b * width / (l0 + l1);
    model.bends.push_back(e);
  };
  for (int j = 0; j < nv; ++j) {
    const double w = (j == 0 || j == nv - 1) ? 0.5 * dv : dv;
    for (int i = 1; i + 1 < nu; ++i) {
      add_line(mesh.Index(i - 1, j), mesh.Index(i, j), mesh.Index(i + 1, j), du, du, w, bending_u_Nm);
    }
  }
  for (int i = 0; i < nu; ++i) {
    const double w = (i == 0 || i == nu - 1) ? 0.5 * du : du;
    for (int j = 1; j + 1 < nv; ++j) {
      add_line(mesh.Index(i, j - 1), mesh.Index(i, j), mesh.Index(i, j + 1), dv, dv, w, bending_v_Nm);
    }
  }

  // Matrix pattern: every particle pair coupled by an element.
  std::vector<std::pair<int, int>> pairs;
  for (const auto& e : model.triangles) {
    pairs.emplace_back(e.p[0], e.p[1]);
    pairs.emplace_back(e.p[1], e.p[2]);
    pairs.emplace_back(e.p[0], e.p[2]);
  }
  for (const auto& e : model.bends) {
    pairs.emplace_back(e.p[0], e.p[1]);
    pairs.emplace_back(e.p[1], e.p[2]);
    pairs.emplace_back(e.p[0], e.p[2]);
  }
  model.pattern = BlockPattern::FromPairs(n, pairs);
  // Off-diagonal blocks no triangle touches hold bending only (lambda alpha_k alpha_l I, two
  // particles apart on a grid line): moved to the end of their row, read as scalars by the
  // product.
  const auto scalar_blocks = [&model] {
    std::vector<unsigned char> is_scalar(model.pattern.cols.size(), 1);
    for (int slot : model.pattern.diag_slot) is_scalar[static_cast<std::size_t>(slot)] = 0;
    for (const auto& e : model.triangles) {
      for (int slot : Slots(model.pattern, e.p)) is_scalar[static_cast<std::size_t>(slot)] = 0;
    }
    return is_scalar;
  };
  model.pattern.MoveToRowEnds(scalar_blocks());
  const std::vector<unsigned char> is_scalar = scalar_blocks();
  for (const auto& e : model.triangles) model.triangle_slots.push_back(Slots(model.pattern, e.p));
  for (const auto& e : model.bends) model.bend_slots.push_back(Slots(model.pattern, e.p));
  model.product_rows = SplitRows::FromPattern(model.pattern, is_scalar);
  for (const auto& slots : model.triangle_slots) {
    std::array<std::int32_t, 9> offsets{};
    for (std::size_t k = 0; k < 9; ++k) {
      HAPTEX_DEMAND(slots[k] <= INT32_MAX / static_cast<int>(sizeof(Eigen::Matrix3d)));
      offsets[k] = slots[k] * static_cast<std::int32_t>(sizeof(Eigen::Matrix3d));
    }
    model.triangle_block_offsets.push_back(offsets);
  }
  model.triangle_first_blocks = internal::TriangleFirstBlocks(model.triangle_slots, model.pattern.num_blocks());
  std::vector<unsigned char> touched(static_cast<std::size_t>(model.pattern.num_blocks()), 0);
  for (const auto& slots : model.triangle_slots) {
    for (int slot : slots) touched[static_cast<std::size_t>(slot)] = 1;
  }
  const SplitRows& split = model.product_rows;
  for (std::size_t r = 0; r < static_cast<std::size_t>(n); ++r) {
    const int first = split.general_first_slot[r];
    for (int slot = first; slot < first + split.general_start[r + 1] - split.general_start[r]; ++slot) {
      if (!touched[static_cast<std::size_t>(slot)]) model.general_slots_without_triangles.push_back(slot);
    }
  }
  return model;
}

}  // namespace haptex::textile
