#include "cli/tactile_command.h"

#include <filesystem>
#include <iostream>
#include <memory>

#include "libs/scene/fabric_database.h"
#include "libs/scene/tactile_fabric.h"
#include "libs/tactile/grey_image.h"
#include "libs/tactile/spectrum.h"

namespace haptex::cli {
namespace {

struct BuildOptions {
  std::string fabric;
  std::string out;
  std::string png_prefix;
  scene::TactileSurfaceOverrides surface;
};

int Build(const BuildOptions& options) {
  const scene::FabricDatabase db(scene::FabricDatabase::DefaultDirectory());
  const v1::Fabric fabric = db.Load(options.fabric);
  const scene::VirtualFabric v = scene::BuildVirtualFabric(fabric, options.surface);
  const std::string out = options.out.empty() ? "runs/tactile/" + options.fabric + ".tile" : options.out;
  if (const auto dir = std::filesystem::path(out).parent_path(); !dir.empty()) std::filesystem::create_directories(dir);
  v.tile.SaveFile(out);
  const Eigen::Matrix2d& b = v.tile.basis_m();
  std::cout << "tactile surface of " << options.fabric << ": " << v.height_map.size_x() << " x "
            << v.height_map.size_y() << " height map -> periodic tile " << v.tile.samples_s() << " x "
            << v.tile.samples_t() << " samples, lattice a = (" << b(0, 0) * 1e3 << ", " << b(1, 0) * 1e3
            << ") mm, b = (" << b(0, 1) * 1e3 << ", " << b(1, 1) * 1e3 << ") mm, residual rms "
            << v.tile.residual_rms_um() << " um, periodicity index " << v.tile.periodicity_index() << "\n  wrote "
            << out << "\n";
  if (!options.png_prefix.empty()) {
    tactile::WritePngFile(tactile::GreyImageFromArray(v.tile.TileHeightsUm()), options.png_prefix + "_tile.png");
    tactile::WritePngFile(tactile::GreyImageFromArray(v.height_map.height_um()), options.png_prefix + "_map.png");
    const tactile::PowerSpectrum spectrum = tactile::ComputePowerSpectrum(v.height_map);
    tactile::WritePngFile(tactile::GreyImageFromArray((spectrum.power_um2 + 1e-12).log()),
                          options.png_prefix + "_spectrum.png");
    std::cout << "  wrote " << options.png_prefix << "_{tile,map,spectrum}.png\n";
  }
  return 0;
}

}  // namespace

void AddTactileCommand(CLI::App& app, int* exit_code) {
  CLI::App* tactile = app.add_subcommand("tactile", "Virtual tactile fabrics");
  tactile->require_subcommand(1);
  auto o = std::make_shared<BuildOptions>();
  CLI::App* build = tactile->add_subcommand("build", "Build a fabric's tactile surface and its periodic tile");
  build->add_option("fabric", o->fabric, "database name")->required();
  build->add_option("--out", o->out, "tile file (default: runs/tactile/FABRIC.tile)");
  build->add_option("--png", o->png_prefix, "also write PREFIX_tile.png, PREFIX_map.png, PREFIX_spectrum.png");
  build->add_option("--pattern", o->surface.pattern, "weave pattern if the fabric has none: plain, twill, satin");
  build->add_option("--warp-pitch-mm", o->surface.warp_pitch_mm, "warp thread pitch [mm]");
  build->add_option("--weft-pitch-mm", o->surface.weft_pitch_mm, "weft thread pitch [mm]");
  build->add_option("--yarn-mm", o->surface.yarn_diameter_mm, "yarn diameter [mm]");
  build->add_option("--smd-um", o->surface.smd_um, "roughness KES SMD [um]");
  build->add_option("--image", o->surface.image_path, "a PGM height image instead of a weave");
  build->add_option("--image-pixel-um", o->surface.image_pixel_um, "the image's pixel size [um]");
  build->callback([o, exit_code] { *exit_code = Build(*o); });
}

}  // namespace haptex::cli
