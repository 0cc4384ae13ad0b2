// The checks of a case that need its parts together: the grid with the bodies and the
// boundary conditions, and the places the output goes. Case::read checks every
// dictionary on its own; check_setup runs what the run's setup would reject, without
// allocating the run, stepping or writing anything. `scree --check` runs it, and so
// does every Simulation before it builds the run, so that the run and --check accept
// the same cases and every problem is reported together with its file:line.
//
//   Case c = Case::read(dir, rt);
//   SetupReport r = check_setup(c, rt);      // r.errors: the run would fail
//   for (auto& w : r.warnings) ...           // the run goes on, probably not as meant
//
// It also knows where the writers and function objects of a case write
// (output_places), so that `scree` can refuse to replace the results of an earlier run
// (existing_results) unless told to (--overwrite).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "scree/case/case.hpp"
#include "scree/boundary/boundary_condition.hpp"
#include "scree/case/case_model.hpp"
#include "scree/case/memory_estimate.hpp"
#include "scree/exec/memory.hpp"
#include "scree/io/dictionary.hpp"
#include "scree/plugin/loader.hpp"

namespace scree {

class BoundaryCondition;

struct SetupReport {
  std::vector<InputError> errors;    ///< what the run would reject (file:line each)
  std::vector<InputError> warnings;  ///< what the run accepts but is probably a mistake
  std::string memory;  ///< the memory the run needs and what is free, e.g. "about 2.10 MB of host memory (23.4 GB free)"
  /// What the run will be, a line each: its points (per body), grid, steps and writes.
  std::vector<std::string> summary;
};

/// For a case Case::read accepted:
///   memory       the run's estimated memory fits in what is free on the host and, on
///                `device` cuda, on the GPU (check_memory, memory_estimate.hpp); where it
///                does not, the checks below are not run (they visit every node and
///                particle position, which such a case has too many of);
///   bodies       each region fits the case and the grid, holds particles, and does not
///                overlap another body (check_bodies, particle_generation.hpp);
///   boundaries   each boundary condition builds on this grid (a face zMin in 2D, a
///                region that selects nothing it can use, ...): the plugins are
///                constructed on the host and constrain a scratch set of walls;
///   output       (with_output) every writer's and function object's directory can be
///                created and written (nothing is created); one outside the case
///                directory is a warning.
SCREE_API SetupReport check_setup(const Case& c, PluginRuntime& rt, bool with_output = true,
                                  Device device = Device::cpu, RankLayout layout = {});

/// Where a writer or function object writes.
struct OutputPlace {
  std::string owner;          ///< "writer 'particles'", "function object 'front'"
  std::filesystem::path dir;  ///< its directory (relative to the working directory, like the case's)
  SourceLocation where;       ///< its `directory` entry, or its dictionary when defaulted
  /// Which files in `dir` are its own: those named <prefix>.* or <prefix>_* (a writer
  /// names its files after itself: VTK/particles.pvd, VTK/particles_3.vtp). Empty: every
  /// file (the directory is its own: postProcessing/<name>/ of a function object).
  std::string prefix;
};

/// The places of the writers (those whose plugin declares a `directory` parameter) and
/// of the function objects (postProcessing/<name>/) of a validated case.
SCREE_API std::vector<OutputPlace> output_places(const Case& c, const Registry& reg);

/// The error of boundary condition `e` (made as `made`) that acts on the pore liquid (a
/// hydraulic condition, or a wall with `drained yes`) in a case without a two-phase body;
/// empty when it has none. The setup check and the run say the same.
SCREE_API std::vector<InputError> needs_two_phase(const Entry& e, const BoundaryCondition& made, bool two_phase);

/// What a run of case `c` will be, from the memory estimate's counts (so the points are
/// estimated: region volume x particlesPerCell / cellSize^D): the points per body, the grid,
/// the steps (exact with a fixed deltaT; a lower bound with adjustTimeStep, whose steps the
/// points' wave speed sets) and the writes. check_setup fills SetupReport::summary with it.
struct MemoryEstimate;
SCREE_API std::vector<std::string> run_summary(const Case& c, const MemoryEstimate& m);

/// Conditions of one type on the pore liquid (porous/hydraulic_condition.hpp) that act on
/// the same nodes of `grid` in overlapping time windows: the run applies one after the
/// other, and the result is not what either entry says (two rainfalls give the smaller
/// intensity there, two pore pressures the later one). An error at the later entry naming
/// the earlier one, the shared nodes and the common window, for each such pair. `made[i]`
/// is the condition made from `entries[i]`. The setup check and the run say the same.
SCREE_API std::vector<InputError> overlapping_hydraulic_conditions(const std::vector<const Entry*>& entries,
                                                                   const std::vector<const BoundaryCondition*>& made,
                                                                   const NodeLattice& grid);

/// The results an earlier run left where this case's writers and function objects
/// write (hidden temporaries aside), which a run from t = 0 replaces: their files, in
/// order of the places.
SCREE_API std::vector<std::filesystem::path> existing_results(const Case& c, const Registry& reg);

/// Remove the hidden temporaries (".<file>.tmp<pid>_<n>": write_file_atomically) a killed
/// run left where this case's writers and function objects write; returns how many. Only
/// under the case's RunLock (run_lock.hpp): another run's temporaries are files it is
/// writing.
SCREE_API std::size_t remove_temporaries(const Case& c, const Registry& reg);

}  // namespace scree
