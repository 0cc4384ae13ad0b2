// scree-element: element tests (simple shear, triaxial, isotropic compression) of any
// registered material, loaded through the plugin runtime.
//
//   scree-element DICT -o OUT.csv
//
// DICT holds `material { type ...; }`, `initialStress { ... }` and `loading { ... }`
// (element_program.hpp). The CSV header states units and sign conventions.
#include <boost/program_options.hpp>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>

#include "element_driver.hpp"
#include "element_program.hpp"
#include "scree/io/dictionary.hpp"
#include "scree/plugin/loader.hpp"

namespace po = boost::program_options;

namespace {

constexpr const char* kUsage =
    "Usage: scree-element DICT -o OUT.csv\n"
    "Element test of one material point of a Scree material plugin.\n\n"
    "DICT (OpenFOAM syntax):\n"
    "  material      { type phaseTransition; particleDensity 1050; ... }\n"
    "  initialStress { type K0; verticalStress 500; K0 0.5; }     // or: type isotropic; pressure 1e5;\n"
    "  loading\n"
    "  {\n"
    "      type      undrainedSimpleShear;  // drainedSimpleShear drainedTriaxial undrainedTriaxial\n"
    "                                       // isotropicCompression\n"
    "      segments  { a { duration 0.5; rate 10; } b { duration 19.5; acceleration 50; } }\n"
    "      timeStep  1e-4;                  // or: increments N;\n"
    "      outputInterval 0.02;\n"
    "      control   constantCellPressure;  // drainedTriaxial: or constantMeanStress\n"
    "  }\n"
    "Plugins are loaded from SCREE_PLUGIN_PATH and <prefix>/lib/scree/plugins.\n\n"
    "Options";

}  // namespace

int main(int argc, char** argv) {
  std::string dict_path, out_path;
  po::options_description opts(kUsage);
  opts.add_options()("help,h", "print this help")("output,o", po::value<std::string>(&out_path),
                                                   "output CSV file (required)")(
      "list", "list the registered material types and exit");
  po::options_description hidden;
  hidden.add_options()("dict", po::value<std::string>(&dict_path));
  po::positional_options_description pos;
  pos.add("dict", 1);
  po::options_description all;
  all.add(opts).add(hidden);
  po::variables_map vm;
  try {
    po::store(po::command_line_parser(argc, argv).options(all).positional(pos).run(), vm);
    po::notify(vm);
  } catch (const std::exception& e) {
    std::cerr << "scree-element: " << e.what() << "\n\n" << opts << "\n";
    return 2;
  }
  if (vm.count("help")) {
    std::cout << opts << "\n";
    return 0;
  }
  try {
    scree::PluginRuntime rt;
    rt.load_default_plugins();
    if (vm.count("list")) {
      for (const auto& n : rt.registry().names(scree::PluginKind::material)) std::cout << n << "\n";
      return 0;
    }
    if (dict_path.empty() || out_path.empty()) {
      std::cerr << "scree-element: need DICT and -o OUT.csv\n\n" << opts << "\n";
      return 2;
    }
    const scree::Dictionary dict = scree::Dictionary::read_file(dict_path);
    std::vector<scree::InputError> errors;
    scree::validate(scree::element::element_spec(), dict, errors);
    if (!errors.empty()) throw scree::InputErrors(std::move(errors));
    const scree::element::Program program = scree::element::read_program(dict);
    auto material = rt.registry().make_point_material(dict.sub("material"));
    int status = 0;
    {
      scree::element::ErasedElementPoint point(std::move(material));
      std::ofstream csv(out_path);
      if (!csv) {
        std::cerr << "scree-element: cannot write '" << out_path << "'\n";
        return 1;
      }
      // the header needs the extra column names: map the fields once
      std::vector<std::string> names;
      scree::element::detail::map_fields(point, names);
      scree::element::write_csv_header(csv, point, program, names, dict_path);
      const auto res = scree::element::run(
          point, program, [&](const scree::element::Row& r) {
            scree::element::write_csv_row(csv, r, program.loading == scree::element::Loading::drainedTrueTriaxial);
          }, false);
      std::cout << "scree-element: " << res.increments << " increments of " << program.dt << " s, "
                << "material " << point.type_name() << ", wrote " << out_path << "\n";
      if (res.newton_failures > 0) {
        std::cerr << "scree-element: warning: the stress conditions did not converge in " << res.newton_failures
                  << " increments (largest residual " << res.max_residual << " Pa)\n";
        status = 3;
      }
    }
    return status;
  } catch (const scree::InputErrors& e) {
    std::cerr << e.what() << "\n";
    return 1;
  } catch (const scree::InputError& e) {
    std::cerr << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "scree-element: " << e.what() << "\n";
    return 1;
  }
}
