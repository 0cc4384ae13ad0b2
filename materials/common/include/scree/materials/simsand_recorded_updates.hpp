// Recorded SIMSAND stress updates: the lines a diagnostic build prints for every update of
// more than SCREE_SIMSAND_REPORT_SUBSTEPS substeps (simsand_integrator.hpp, integrate()),
//
//   simsand-substeps N apex A sig s0 .. s5 e E kappa K deps d0 .. d5
//
// read back to replay them (scree-bench's `updates`, the tests). Host code only. Lines that
// do not start with "simsand-substeps" (comments) are skipped.
#pragma once

#include <istream>
#include <sstream>
#include <string>
#include <vector>

#include "scree/core/tensor.hpp"
#include "scree/materials/simsand_params.hpp"

namespace scree::materials::simsand {

struct RecordedUpdate {
  int substeps = 0;  ///< the substeps the update took when it was recorded
  bool apex = false;  ///< it ended at the stress-free apex
  Sym3 sig;          ///< the input stress (tension positive) [Pa]
  Vars v;            ///< the input void ratio and kappa (epsEq is not recorded: 0)
  Sym3 deps;         ///< the strain increment (tension positive)
};

inline std::vector<RecordedUpdate> read_recorded_updates(std::istream& in) {
  std::vector<RecordedUpdate> ups;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("simsand-substeps", 0) != 0) continue;
    std::istringstream is(line);
    std::string w;
    int apex = 0;
    RecordedUpdate u{};
    is >> w >> u.substeps >> w >> apex >> w;
    for (int i = 0; i < 6; ++i) is >> u.sig[i];
    is >> w >> u.v.e >> w >> u.v.kappa >> w;
    for (int i = 0; i < 6; ++i) is >> u.deps[i];
    u.apex = apex != 0;
    if (is) ups.push_back(u);
  }
  return ups;
}

}  // namespace scree::materials::simsand
