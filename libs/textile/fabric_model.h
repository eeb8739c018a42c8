#pragma once
// Read-only description of one simulated fabric: topology, rest geometry, masses, material laws,
// element weights and the fixed matrix pattern (MuJoCo's mjModel, in spirit).

#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "libs/textile/block_pattern.h"
#include "libs/textile/grid_mesh.h"
#include "libs/textile/kes_material.h"

namespace haptex::textile {

/// Damping of each deformation mode, stiffness-proportional: damping force per width =
/// time constant x tangent stiffness x strain rate.
struct DampingOptions {
  double stretch_s = 1e-3;  ///< tensile mode [s]
  double shear_s = 1e-3;    ///< shear mode [s]
  double bend_s = 1e-3;     ///< bending mode [s]
};

/// Air drag (air at rest).
struct DragOptions {
  double linear_N_s_per_m3 = 0.02;     ///< viscous drag per area: F = -c A v
  double quadratic_coefficient = 1.5;  ///< C_d for the normal velocity component
  double air_density_kg_per_m3 = 1.2;
};

/// Model-building options; all are inputs, none are constants of the code.
struct ModelOptions {
  DampingOptions damping;
  DragOptions drag;
  Eigen::Vector3d gravity_m_per_s2{0.0, 0.0, -9.81};  ///< world frame
  /// The fabric's orientation on the grid: the warp direction's angle from the grid's u axis
  /// towards v [rad] (0: warp along u, weft along v; pi/4: a strip cut on the bias). With it,
  /// GridSpec's "warp"/"weft" extents and particle counts are the grid's u and v, not the yarns'.
  double material_angle_rad = 0.0;
};

/// One triangle: U = sum a_k x_k (warp vector), V = sum b_k x_k (weft vector), rest area. The
/// weights already hold the material angle: U and V are the yarn directions, whatever the grid.
struct TriangleElement {
  std::array<int, 3> p{};
  std::array<double, 3> a{}, b{};
  double area_m2 = 0.0;
};

/// One bending triplet along a grid line: R = sum alpha_k x_k, energy lambda |R|^2 / 2; lambda
/// holds the rigidity for curvature along that grid line: at an angle phi from the warp,
/// B_warp cos^2 phi + B_weft sin^2 phi (docs/fabric-model.md section 4).
struct BendElement {
  std::array<int, 3> p{};
  std::array<double, 3> alpha{};
  double lambda_N_per_m = 0.0;
};

/// Everything constant during a simulation.
struct FabricModel {
  GridMesh mesh;
  FabricMaterial material;
  ModelOptions options;
  int num_particles = 0;
  Eigen::VectorXd mass_kg;  ///< lumped masses, size n
  Eigen::VectorXd area_m2;  ///< area represented by each particle, size n
  std::vector<TriangleElement> triangles;
  std::vector<BendElement> bends;
  BlockPattern pattern;
  std::vector<std::array<int, 9>> triangle_slots;  ///< block slot of (p_k, p_l), k*3+l
  std::vector<std::array<int, 9>> bend_slots;
  /// triangle_slots as byte offsets (slot x sizeof(Matrix3d)): the triangle kernel's addresses.
  std::vector<std::array<std::int32_t, 9>> triangle_block_offsets;
  /// Per triangle, entry k*3+l 1 when its block (p_k, p_l) is the first addition the triangle
  /// kernel makes to that slot in a pass (internal::TriangleFirstBlocks), else 0: a step's kernel
  /// reads that block from the constant part of the system instead of resetting it first. Bytes,
  /// not bits: the kernel indexes its two source arrays with them (no bit test or select).
  std::vector<std::array<std::uint8_t, 9>> triangle_first_blocks;
  /// General slots (product_rows) no triangle touches: a step resets these itself.
  std::vector<int> general_slots_without_triangles;
  /// The pattern split for the system product: blocks only bending couples (two particles apart
  /// on a grid line) are a constant scalar times I.
  SplitRows product_rows;
};

/// Builds a model. @throws std::invalid_argument for bad options (negative damping, NaN gravity,
/// non-positive density, ...), naming the option.
FabricModel BuildFabricModel(const FabricMaterial& material, const GridSpec& grid, const ModelOptions& options = {});

}  // namespace haptex::textile
