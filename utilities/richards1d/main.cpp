// scree-richards: the command line of the 1D Richards solver (richards1d.hpp).
#include <cstring>
#include <iostream>
#include <string>
#include <vector>

#include "richards1d.hpp"

namespace {

void usage(std::ostream& os) {
  os << "scree-richards: 1D Richards equation (mixed form, modified Picard of Celia et al. 1990)\n"
        "\n"
        "  scree-richards --config FILE --out DIR [--set key=value]... [--quiet]\n"
        "  scree-richards --help\n"
        "\n"
        "  --config FILE      the problem (utilities/richards1d/README.md; example: infiltration1D/)\n"
        "  --out DIR          writes DIR/profiles.csv, DIR/surface.csv, DIR/front.csv (created if missing)\n"
        "  --set key=value    overrides a key of FILE (repeatable), e.g. --set cells=400 --set top=head\n"
        "  --quiet            no progress, only errors\n"
        "\n"
        "Units SI; z elevation upward from the base; h pressure head [m], negative in suction;\n"
        "fluxes given and written downward positive (infiltration, outflow).\n"
        "\n"
        "Config keys (\"key value;\", // comments, include \"file\"):\n";
  scree::richards1d::print_config_keys(os);
}

}  // namespace

int main(int argc, char** argv) {
  std::string config, out;
  std::vector<std::string> overrides;
  bool quiet = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&](const char* flag) -> std::string {
      if (i + 1 >= argc) {
        std::cerr << "scree-richards: " << flag << " needs a value (--help)\n";
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--help" || a == "-h") {
      usage(std::cout);
      return 0;
    } else if (a == "--config") {
      config = value("--config");
    } else if (a == "--out") {
      out = value("--out");
    } else if (a == "--set") {
      overrides.push_back(value("--set"));
    } else if (a == "--quiet") {
      quiet = true;
    } else {
      std::cerr << "scree-richards: unknown argument '" << a << "' (--help)\n";
      return 2;
    }
  }
  if (config.empty() || out.empty()) {
    std::cerr << "scree-richards: needs --config FILE and --out DIR (--help)\n";
    return 2;
  }
  using namespace scree::richards1d;
  Settings s;
  try {
    std::vector<std::string> warnings;
    s = read_config(config, overrides, &warnings);
    for (const auto& w : warnings) std::cerr << "warning: " << w << '\n';
  } catch (const ConfigError& e) {
    std::cerr << e.what();
    return 1;
  }
  try {
    if (!quiet) {
      std::cout << "scree-richards: " << config << ": L = " << s.height << " m, " << s.cells
                << " cells, K_sat = " << s.soil.K_sat << " m/s, S_s = " << s.soil.S_s << " 1/m, to t = "
                << s.end_time << " s";
      if (s.soil.deformable())
        std::cout << ", deformable skeleton E_oed = " << s.soil.E_oed << " Pa (water load "
                  << (s.soil.water_load ? "on" : "off") << ")";
      std::cout << '\n';
    }
    run(s, out, quiet ? nullptr : &std::cout);
  } catch (const std::exception& e) {
    std::cerr << "scree-richards: " << e.what() << '\n';
    return 3;
  }
  return 0;
}
