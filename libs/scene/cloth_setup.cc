#include "libs/scene/cloth_setup.h"

#include <algorithm>
#include <limits>
#include <stdexcept>

#include "libs/codec/message_conversion.h"
#include "libs/scene/fabric_conversion.h"
#include "libs/scene/scene_defaults.h"
#include "libs/textile/external_force.h"

namespace haptex::scene {
ClothSetup MakeClothSetup(const LoadedScene& loaded) {
  const v1::Scene& scene = loaded.scene;
  const v1::ClothGeometry& cloth = scene.cloth();
  ClothSetup setup;
  setup.material = textile::MaterialFromKes(ToKesFabric(loaded.fabric));

  setup.grid.length_warp_m = ClothWidthM(cloth);
  setup.grid.width_weft_m = ClothHeightM(cloth);
  setup.grid.particles_warp = ClothParticlesU(cloth);
  setup.grid.particles_weft = ClothParticlesV(cloth);

  const Eigen::Vector3d stand = codec::ToEigen(cloth.stand_position_w_m());
  setup.placement.origin_W = stand - Eigen::Vector3d(setup.grid.length_warp_m / 2, 0, 0);
  setup.placement.axis_u_W = Eigen::Vector3d::UnitX();
  const bool flat = cloth.mounting() == v1::ClothGeometry::MOUNTING_FLAT_LEDGE;
  setup.placement.axis_v_W = flat ? Eigen::Vector3d::UnitY() : Eigen::Vector3d(0, 0, -1);

  const int nu = setup.grid.particles_warp;
  const int nv = setup.grid.particles_weft;
  switch (cloth.mounting()) {
    case v1::ClothGeometry::MOUNTING_UNSPECIFIED:
    case v1::ClothGeometry::MOUNTING_TOP_EDGE:
      for (int i = 0; i < nu; ++i) setup.fixed_particles.push_back(i);
      break;
    case v1::ClothGeometry::MOUNTING_TOP_CORNERS:
      setup.fixed_particles = {0, nu - 1};
      break;
    case v1::ClothGeometry::MOUNTING_FLAT_LEDGE: {
      const double dv = setup.grid.width_weft_m / (nv - 1);
      for (int j = 0; j < nv && j * dv <= cloth.ledge_v_m() + 1e-12; ++j) {
        for (int i = 0; i < nu; ++i) setup.fixed_particles.push_back(i + nu * j);
      }
      break;
    }
    default:
      break;
  }
  for (const std::uint32_t p : cloth.fixed_particles()) setup.fixed_particles.push_back(static_cast<int>(p));
  std::sort(setup.fixed_particles.begin(), setup.fixed_particles.end());
  setup.fixed_particles.erase(std::unique(setup.fixed_particles.begin(), setup.fixed_particles.end()),
                              setup.fixed_particles.end());

  setup.model_options.material_angle_rad = ClothMaterialAngleRad(cloth);
  const v1::ModelOptions& m = scene.model();
  if (m.disable_gravity()) setup.model_options.gravity_m_per_s2.setZero();
  if (m.disable_air_drag()) {
    setup.model_options.drag.linear_N_s_per_m3 = 0;
    setup.model_options.drag.quadratic_coefficient = 0;
  } else {
    if (m.air_drag_linear() > 0) setup.model_options.drag.linear_N_s_per_m3 = m.air_drag_linear();
    if (m.air_drag_quadratic() > 0) setup.model_options.drag.quadratic_coefficient = m.air_drag_quadratic();
  }
  if (m.disable_bending()) {
    setup.material.bending_warp_Nm = 0;
    setup.material.bending_weft_Nm = 0;
  }

  textile::StepOptions& step = setup.step_options;
  step.method = IntegratorOr(m.global_integrator(), step.method);
  step.dt_s = OrDefault(m.global_dt_s(), 1.0 / GlobalRateHz(scene));
  if (m.cg_tolerance() > 0) step.cg_tolerance = m.cg_tolerance();
  if (m.cg_max_iterations() > 0) step.cg_max_iterations = static_cast<int>(m.cg_max_iterations());
  if (m.substeps() > 0) step.substeps = static_cast<int>(m.substeps());
  if (m.newton_max_iterations() > 0) step.newton_max_iterations = static_cast<int>(m.newton_max_iterations());
  if (m.newton_tolerance() > 0) step.newton_tolerance = m.newton_tolerance();
  if (m.has_max_step_halvings()) step.max_step_halvings = static_cast<int>(m.max_step_halvings());
  if (m.has_max_strain_rise_per_step()) step.max_strain_rise_per_step = m.max_strain_rise_per_step();
  textile::ValidateStepOptions(step);
  return setup;
}

ClothInstance MakeClothInstance(const ClothSetup& setup) {
  ClothInstance instance{textile::BuildFabricModel(setup.material, setup.grid, setup.model_options), {}};
  instance.state = textile::MakeRestState(instance.model, setup.placement);
  for (const int p : setup.fixed_particles) instance.state.Fix(p);
  return instance;
}

SceneLoads::SceneLoads(const v1::Scene& scene, const textile::FabricModel& model)
    : model_(model), loads_(scene.loads().begin(), scene.loads().end()) {
  const int nu = model.mesh.particles_warp();
  const int nv = model.mesh.particles_weft();
  for (int i = 0; i < nu; ++i) bottom_edge_.push_back(i + nu * (nv - 1));
  for (const v1::Load& load : loads_) {
    if (load.kind() == v1::Load::KIND_POINT && static_cast<int>(load.particle()) >= model.num_particles) {
      throw std::invalid_argument("load on particle " + std::to_string(load.particle()) + ", but the cloth has " +
                                  std::to_string(model.num_particles));
    }
  }
}

double SceneLoads::Factor(const v1::Load& load, double t) {
  if (t < load.start_s()) return 0.0;
  const double end = load.end_s() > 0 ? load.end_s() : std::numeric_limits<double>::infinity();
  if (t > end) return 0.0;
  if (load.ramp_s() <= 0) return 1.0;
  const double in = (t - load.start_s()) / load.ramp_s();
  const double out = (end - t) / load.ramp_s();
  return std::clamp(std::min(in, out), 0.0, 1.0);
}

void SceneLoads::Apply(double t, textile::FabricState* state) const {
  state->external_force_W_N.setZero();
  for (const v1::Load& load : loads_) {
    const double factor = Factor(load, t);
    if (factor == 0.0) continue;
    const Eigen::Vector3d force =
        factor * Eigen::Vector3d(load.force_w_n().x(), load.force_w_n().y(), load.force_w_n().z());
    if (load.kind() == v1::Load::KIND_POINT) {
      state->external_force_W_N.segment<3>(3 * static_cast<int>(load.particle())) += force;
    } else if (load.kind() == v1::Load::KIND_BOTTOM_EDGE) {
      textile::AddEdgeLoad(model_, bottom_edge_, force, state);
    }
  }
}

}  // namespace haptex::scene
