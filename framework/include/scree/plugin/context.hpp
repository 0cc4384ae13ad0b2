// What plugins (boundary conditions, writers, function objects) learn about the case
// when they are constructed.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "scree/core/config.hpp"
#include "scree/exec/memory.hpp"

namespace scree {

class Comm;

struct SolverContext {
  std::filesystem::path case_dir;  ///< the case directory
  std::string name;                ///< the plugin instance's name (its dictionary key)
  int dimension = 2;
  Device device = Device::cpu;
  // Background grid (see mpm/grid.hpp); vectors have `dimension` entries.
  std::vector<Real> grid_origin, domain_lower, domain_upper;
  std::vector<int> grid_nodes;
  Real cell_size = 0;
  std::vector<std::string> body_names;
  std::vector<Real> gravity;
  Real start_time = 0, end_time = 0, delta_t = 0;
  /// The ranks a function object that reduces over ranks combines its statistics over
  /// (output/ranks.hpp): those of a decomposed run, or null for one rank.
  std::shared_ptr<Comm> comm;
  /// <case>/postProcessing/<name>: where a function object writes (created on first use).
  std::filesystem::path post_processing_dir() const { return case_dir / "postProcessing" / name; }
};

}  // namespace scree
