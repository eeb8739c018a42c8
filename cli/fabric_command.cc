#include "cli/fabric_command.h"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "launch/gnuplot.h"
#include "libs/scene/fabric_conversion.h"
#include "libs/scene/fabric_database.h"
#include "libs/textile/kes_material.h"

namespace haptex::cli {
namespace {

constexpr double kDegToRad = 3.14159265358979323846 / 180.0;

int List() {
  const scene::FabricDatabase db(scene::FabricDatabase::DefaultDirectory());
  std::cout << std::left << std::setw(34) << "name" << std::right << std::setw(8) << "W g/m2" << std::setw(10)
            << "EMT w/f %" << std::setw(16) << "B w/f uN m" << std::setw(8) << "G"
            << "  source\n";
  int failed = 0;
  for (const std::string& name : db.Names()) {
    try {
      const v1::Fabric f = db.Load(name);
      std::ostringstream emt, b;
      // sources with a digitized tensile curve have no EMT
      if (f.warp_tensile().loading_curve_size() > 0) {
        emt << "curve";
      } else {
        emt << std::fixed << std::setprecision(1) << f.warp_tensile().emt_percent() << "/"
            << f.weft_tensile().emt_percent();
      }
      b << std::fixed << std::setprecision(1) << f.warp_bending().b_gfcm2_per_cm() * textile::kGfCm2PerCmToNm * 1e6
        << "/" << f.weft_bending().b_gfcm2_per_cm() * textile::kGfCm2PerCmToNm * 1e6;
      std::cout << std::left << std::setw(34) << name << std::right << std::setw(8) << std::fixed
                << std::setprecision(0) << f.weight_mg_per_cm2() * 10.0 << std::setw(10) << emt.str() << std::setw(16)
                << b.str() << std::setw(8) << std::setprecision(2) << f.shear().g_gf_per_cm_deg() << "  "
                << f.source().citation().substr(0, 60) << "\n";
    } catch (const std::exception& e) {
      std::cerr << e.what() << "\n";
      ++failed;
    }
  }
  return failed == 0 ? 0 : 2;
}

// Tables of the three material laws over the range that matters for the fabric.
struct CurveTables {
  std::vector<double> strain, warp_N_per_m, weft_N_per_m, shear_deg, shear_N_per_m;
};

CurveTables Tabulate(const textile::FabricMaterial& m, const v1::Fabric& f, int points) {
  CurveTables t;
  const double emt = std::max(f.warp_tensile().emt_percent(), f.weft_tensile().emt_percent()) / 100.0;
  const double max_strain = emt > 0 ? 1.2 * emt : 0.1;
  for (int i = 0; i <= points; ++i) {
    const double e = max_strain * i / points;
    t.strain.push_back(e);
    t.warp_N_per_m.push_back(m.tensile_warp.Value(e));
    t.weft_N_per_m.push_back(m.tensile_weft.Value(e));
    const double angle = 10.0 * i / points;
    t.shear_deg.push_back(angle);
    t.shear_N_per_m.push_back(m.shear.Value(angle * kDegToRad));
  }
  return t;
}

void PrintKes(const v1::Fabric& f) {
  std::cout << f.name() << ": " << f.description() << "\n  source: " << f.source().citation() << " ("
            << f.source().locator() << ")\n"
            << "  direction known: " << (f.direction_known() ? "yes" : "no (warp and weft carry the same values)")
            << "\n"
            << "  KES        warp            weft\n"
            << "  EMT %      " << std::setw(8) << f.warp_tensile().emt_percent() << "        "
            << f.weft_tensile().emt_percent() << "\n"
            << "  LT         " << std::setw(8) << f.warp_tensile().lt() << "        " << f.weft_tensile().lt() << "\n"
            << "  WT gfcm/cm2" << std::setw(8) << f.warp_tensile().wt_gfcm_per_cm2() << "        "
            << f.weft_tensile().wt_gfcm_per_cm2() << "\n"
            << "  B gfcm2/cm " << std::setw(8) << f.warp_bending().b_gfcm2_per_cm() << "        "
            << f.weft_bending().b_gfcm2_per_cm() << "\n"
            << "  G gf/cm/deg " << f.shear().g_gf_per_cm_deg() << "   W mg/cm2 " << f.weight_mg_per_cm2() << "   T mm "
            << f.thickness_mm() << "   SMD um " << f.surface().smd_um() << "\n";
  for (const auto& flag : f.flags()) {
    std::cout << "  flagged " << flag.field() << ": printed " << flag.as_printed() << "; " << flag.problem()
              << "; used: " << flag.resolution() << "\n";
  }
}

// Draws in a private folder with fixed file names, then copies the picture to `png`: neither the
// user's path nor any other text reaches the script as code (the title goes through GnuplotLabel).
void Plot(const CurveTables& t, const std::string& name, const std::string& png) {
  std::string pattern = (std::filesystem::temp_directory_path() / "haptex-plot-XXXXXX").string();
  if (mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("cannot create a folder for the plot");
  const std::string dir = pattern;
  {
    std::ofstream out(dir + "/curves.dat");
    for (std::size_t i = 0; i < t.strain.size(); ++i) {
      out << t.strain[i] * 100 << ' ' << t.warp_N_per_m[i] << ' ' << t.weft_N_per_m[i] << ' ' << t.shear_deg[i] << ' '
          << t.shear_N_per_m[i] << '\n';
    }
  }
  std::ofstream(dir + "/curves.gp") << "set terminal pngcairo size 1200,450 noenhanced\nset output 'curves.png'\n"
                                    << "set multiplot layout 1,2 title " << launch::GnuplotLabel(name) << "\nset grid\n"
                                    << "set xlabel 'strain [%]'\nset ylabel 'force per width [N/m]'\n"
                                    << "plot 'curves.dat' u 1:2 w lp t 'warp', '' u 1:3 w lp t 'weft'\n"
                                    << "set xlabel 'shear angle [deg]'\n"
                                    << "plot 'curves.dat' u 4:5 w lp t 'shear'\nunset multiplot\n";
  const std::string error = launch::RunGnuplot(dir, "curves.gp");
  std::error_code copied;
  if (error.empty()) {
    std::filesystem::copy_file(dir + "/curves.png", png, std::filesystem::copy_options::overwrite_existing, copied);
  }
  std::error_code ignored;
  std::filesystem::remove_all(dir, ignored);
  if (!error.empty()) throw std::runtime_error(error);
  if (copied) throw std::runtime_error("cannot write " + png + ": " + copied.message());
  std::cout << "wrote " << png << "\n";
}

int Show(const std::string& name, const std::string& png, int points) {
  const scene::FabricDatabase db(scene::FabricDatabase::DefaultDirectory());
  const v1::Fabric fabric = db.Load(name);
  const textile::FabricMaterial material = textile::MaterialFromKes(scene::ToKesFabric(fabric));
  PrintKes(fabric);
  std::cout << "  SI: density " << material.density_kg_per_m2 << " kg/m2, bending warp/weft "
            << material.bending_warp_Nm << "/" << material.bending_weft_Nm << " N m, thickness " << material.thickness_m
            << " m\n\n";
  const CurveTables t = Tabulate(material, fabric, points);
  std::cout << "  strain %   warp N/m    weft N/m   | shear deg   shear N/m\n";
  for (std::size_t i = 0; i < t.strain.size(); ++i) {
    std::cout << std::fixed << std::setprecision(3) << std::setw(10) << t.strain[i] * 100 << std::setw(12)
              << t.warp_N_per_m[i] << std::setw(12) << t.weft_N_per_m[i] << "   |" << std::setw(10) << t.shear_deg[i]
              << std::setw(12) << t.shear_N_per_m[i] << "\n";
  }
  if (!png.empty()) Plot(t, name, png);
  return 0;
}

}  // namespace

void AddFabricCommand(CLI::App& app, int* exit_code) {
  CLI::App* fabric = app.add_subcommand("fabric", "The fabric database (data/fabrics)");
  fabric->require_subcommand(1);
  CLI::App* list = fabric->add_subcommand("list", "List the fabrics with key values and sources");
  list->callback([exit_code] { *exit_code = List(); });
  auto name = std::make_shared<std::string>();
  auto png = std::make_shared<std::string>();
  auto points = std::make_shared<int>(12);
  CLI::App* show = fabric->add_subcommand("show", "Print a fabric's KES values and material curves");
  show->add_option("name", *name, "database name")->required();
  show->add_option("--plot", *png, "also draw the curves into this PNG (gnuplot)");
  show->add_option("--points", *points, "table rows per curve")->check(CLI::Range(2, 1000));
  show->callback([name, png, points, exit_code] { *exit_code = Show(*name, *png, *points); });
}

}  // namespace haptex::cli
