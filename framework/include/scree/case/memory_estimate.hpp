// How much memory a case's run takes, estimated from its dictionaries before anything is
// allocated, and the check that it fits in the memory that is free.
//
// The grid: its nodes (system/gridDict: the domain over cellSize, plus the ghost layers)
// times the bytes the solver keeps per node (solver_setup.cpp: two sets of 1 + 4 D nodal
// fields; the tiles' stamps; the wall masks; with a two-phase body the liquid's two sets of
// kLiquidFieldCount fields, its cell counts, surface flags, balance and masks,
// porous_media.cpp). The points: each body's region area (volume) times
// (particlesPerCell / cellSize)^D (estimate_particle_count), times the bytes per point:
// the particle block (particle_storage.hpp: 3 D + D^2 + the stress components + 3 columns,
// D^2 more with APIC, the material's state Reals, a two-phase body's 4 + 2 D extra
// columns), the elastic-first split's list, the sort's keys, permutation and scratch
// (particle_sort.hpp) and, on the GPU, the snapshot's device copy (snapshot_copy.hpp); on
// the host, the larger of the setup's copies (the generated positions, velocities,
// volumes and stresses, and the host block uploaded) and the output's (the host copy of
// the block, and three snapshots' fields: one written, the writer's copy of it, one being
// taken, output/snapshot.hpp).
//
//   MemoryEstimate m = estimate_memory(c, rt.registry(), Device::cpu, true);
//   std::vector<InputError> e = check_memory(c, rt.registry(), Device::cpu, true);
//
// check_memory compares the peaks with mem::available (MemAvailable, the cgroup's limit,
// cudaMemGetInfo) and, where one does not fit, names the entry that drives it (cellSize
// for the grid, a body's particlesPerCell for its points) with the bytes needed and free
// and what would fit. check_setup runs it first (scree --check, and every run).
#pragma once

#include <string>
#include <vector>

#include "scree/case/case.hpp"
#include "scree/exec/memory.hpp"
#include "scree/io/dictionary.hpp"
#include "scree/plugin/registry.hpp"

namespace scree {

/// How a run is spread: over `ranks` processes (mpirun; one GPU each), `per_node` of them
/// on one machine. A rank's backend holds its box of the grid with the halo and about
/// 1/ranks of the points, up to kRebalanceRatio times that before the boxes move
/// (case/decomposition.hpp). Each rank makes only the points of its box and writes them
/// as its own piece; the first rank also gathers the whole case when a function object
/// that does not reduce over ranks is due (output/function_object.hpp), and the ranks of
/// one machine share its host memory.
struct RankLayout {
  int ranks = 1;
  int per_node = 1;
};

/// One part of a case's memory: the grid, or a body's points.
struct MemoryPart {
  std::string what;      ///< "the grid", "body 'column'"
  std::string key;       ///< the entry that sets how many: "cellSize", "particlesPerCell"
  SourceLocation where;  ///< that entry's file:line (its dictionary's where it is defaulted)
  double count = 0;      ///< nodes or points
  double backend_each = 0;  ///< bytes per node or point in the backend's memory (mem::allocate)
  double host_each = 0;     ///< bytes per node or point a rank holds on the host at the peak, besides the backend's
  double host_root_each = 0;  ///< bytes per node or point of the whole count the first rank gathers besides
  double rank_share = 1;    ///< the fraction of `count` one rank holds (backend and host)
  double backend() const { return count * rank_share * backend_each; }
  /// The first rank's host bytes (a run on one rank: the run's).
  double host() const { return count * (rank_share * host_each + host_root_each); }
  /// The host bytes of a machine running `per_node` ranks, the first among them.
  double node_host(int per_node) const { return count * (per_node * rank_share * host_each + host_root_each); }
};

struct SCREE_API MemoryEstimate {
  Device device = Device::cpu;
  RankLayout layout;
  std::vector<MemoryPart> parts;  ///< the grid first, then each body
  /// What goes through mem::allocate on one rank's backend: nodal fields, particle arrays,
  /// sort buffers, masks (mem::peak_bytes(device) counts the same).
  double backend_bytes() const;
  /// The peaks: one machine's host (its ranks', with their backends' bytes on the CPU
  /// backend) and one rank's device (0 on the CPU).
  double host_bytes() const;
  double device_bytes() const;
};

/// The estimate for a case Case::read accepted, on `device`; `with_output`: writers and
/// function objects take snapshots.
SCREE_API MemoryEstimate estimate_memory(const Case& c, const Registry& reg, Device device, bool with_output,
                                         RankLayout layout = {});

/// An error per memory space (host; the device's with Device::cuda) the estimate does not
/// fit in, at the entry that drives it; empty when it fits or the free memory is unknown.
SCREE_API std::vector<InputError> check_memory(const Case& c, const Registry& reg, Device device, bool with_output,
                                               RankLayout layout = {});

}  // namespace scree
