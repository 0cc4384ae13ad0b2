// KernelPolicy: every switch that changes how fast a step runs, never what it computes
// (within the round-off of the order of additions), in one place. The solver and
// scree-bench set them here (`scree` itself only --reference-kernels and --no-graphs: the
// A/B switches that time one kernel against another are scree-bench's); docs/performance.md
// says what each is worth.
//
//   reference     the straightforward kernels, for verification and timing: one generic
//                 particle kernel with an atomic per particle and node, every grid node in
//                 the grid updates, the signal speed every step, no particle sorting
//   sparseGrid    fast kernels: grid updates on the tiles particles touched only
//   graphs        CUDA: replay the steps as captured CUDA graphs
//   split         fast kernels, materials with update_elastic: the stress pass as an
//                 elastic-only kernel plus one for the points it defers (automatic: on
//                 CUDA the solver times both ways now and then and keeps the faster,
//                 split_tuner.hpp; off on the CPU)
//   refill        CUDA, the split's deferred points of a material whose update runs in turns
//                 (material.hpp): lanes take new points as theirs finish (on; with the
//                 automatic split the tuner times the split with and without them and keeps
//                 the faster), or one point per lane for the whole pass (off; scree
//                 --no-refill, scree-bench no-refill)
//   refillLanes   with refill: how many lanes of a warp are done before they take new points
//                 together (scree-bench refill-lanes-N)
//   stress cap    CUDA, 2D: the stress kernel's register cap, as blocks of 64 threads per SM
//   elastic cap   CUDA, 2D: the split's elastic-only kernel's register cap
//   speedEvery    fixed step: the signal speed (the stopCo health check's only use of it)
//                 measured every this many steps; the adaptive step measures it every step
//   sortInterval  is a case setting (system/mpmSchemes); the reference kernels never sort
//   healthChecks  the (single-phase) grid update's non-finite probe and a fixed step's stopCo speed
//                 samples (on; off only to measure what they cost: scree-bench --kernels
//                 no-health. A run without them does not stop on a blow-up)
//   ledgerTransfer  the energy ledger (energies' `budget yes`): its transfer pass in a kernel of
//                 its own, compiled without the stress update (on), or in the ledger's whole-pass
//                 kernel (off; scree-bench --kernels ledger-whole: what the light one saves)
//   ledgerSplit   the energy ledger's stress pass split as the fast one's (elastic-first, the
//                 split chosen by timing) or always whole (off; scree-bench --kernels
//                 ledger-unsplit)
//
// A register cap is a compile-time launch bound, so only the values a kernel was compiled
// for exist: check() rejects any other rather than run it uncapped without a word.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <string>

namespace scree {

enum class StressSplit { automatic, on, off, alternate /* on and off by turns, a chunk each (tests) */ };

struct KernelPolicy {
  /// Register caps the kernels are compiled for (blocks of 64 threads per SM; 0: the
  /// compiler's choice). Stress: 6 blocks = 170 registers, 12 warps per SM, faster at rest
  /// than the compiler's 254 registers (more warps hide the latency of the material's
  /// update). Elastic-only: 10 blocks = 96 registers, 20 warps per SM (the compiler alone
  /// takes 146).
  static constexpr int kStressCap = 6;
  static constexpr int kElasticCap = 10;
  static constexpr std::initializer_list<int> kStressCaps = {0, kStressCap};
  static constexpr std::initializer_list<int> kElasticCaps = {0, kElasticCap};

  bool reference = false;
  bool sparse_grid = true;
  bool graphs = true;
  StressSplit split = StressSplit::automatic;
  /// The split's deferred points as a queue that a lane draws from when its point is done
  /// (DeferredStress, particle_pass.hpp), for materials with an update in turns.
  bool refill = true;
  /// With refill: the lanes of a warp that hold a finished point (or none) before those lanes
  /// take new ones together. Fewer refill more often (each refill runs the start and the end
  /// of updates while the other lanes wait); more leave lanes idle longer. 1 to 32.
  int refill_lanes = 16;
  int stress_blocks_per_sm = kStressCap;
  int elastic_blocks_per_sm = kElasticCap;
  /// A power of 2. An unstable fixed step is then found within this many steps of its first
  /// step above stopCo (a blow-up takes hundreds), and the speed's cost (the dearest for
  /// materials whose wave speed depends on their state, such as phaseTransition) is paid on
  /// one step in this many.
  int speed_every = 64;
  /// The health checks the kernels carry (see the top of this file): the grid update's
  /// probe of the nodal velocity and force, and the stopCo speed samples of a fixed step.
  bool health_checks = true;
  /// The energy ledger's transfer pass (PIC blend and walls booked, no stress update) in its
  /// own light kernel instead of the ledger's whole-pass kernel (which needs every register
  /// and spills). The same sums in the same order.
  bool ledger_light_transfer = true;
  /// The energy ledger's stress pass split as the fast one's (`split`): an elastic-only kernel
  /// that books the elastic points' work, then the whole update over the points it deferred
  /// (unsplit, the ledger's stress pass runs the plastic update's registers on every point).
  bool ledger_split = true;
  /// The energy ledger's kernels by name (scree-bench ledger-NAME): split (both switches
  /// above on, the default), unsplit (ledger_split off) or whole (both off: the ledger's
  /// whole-pass kernel). False, nothing set, for another word.
  static constexpr std::initializer_list<const char*> kLedgerKernels = {"split", "unsplit", "whole"};
  bool set_ledger_kernels(const std::string& name) {
    bool known = false;
    for (const char* w : kLedgerKernels) known = known || name == w;
    if (!known) return false;
    ledger_split = name == "split";
    ledger_light_transfer = name != "whole";
    return true;
  }

  /// The straightforward kernels (see the top of this file).
  static KernelPolicy reference_kernels() {
    KernelPolicy p;
    p.reference = true;
    p.sparse_grid = false;
    return p;
  }
  /// Sparse grid updates in effect (never with the reference kernels).
  bool sparse() const { return sparse_grid && !reference; }
  /// The particle sort interval in effect for the case's sortInterval.
  std::int64_t sort_interval(std::int64_t case_interval) const { return reference ? 0 : case_interval; }

  /// Empty if every value is one the kernels support; else what is wrong and what is valid.
  std::string check() const {
    auto in = [](int v, std::initializer_list<int> ok) {
      for (int x : ok)
        if (x == v) return true;
      return false;
    };
    auto list = [](std::initializer_list<int> ok) {
      std::string s;
      for (int x : ok) s += (s.empty() ? "" : ", ") + std::to_string(x);
      return s;
    };
    if (!in(stress_blocks_per_sm, kStressCaps))
      return "stress kernel register cap " + std::to_string(stress_blocks_per_sm) +
             " blocks per SM is not compiled; valid: " + list(kStressCaps) + " (0: no cap)";
    if (!in(elastic_blocks_per_sm, kElasticCaps))
      return "elastic kernel register cap " + std::to_string(elastic_blocks_per_sm) +
             " blocks per SM is not compiled; valid: " + list(kElasticCaps) + " (0: no cap)";
    if (refill_lanes < 1 || refill_lanes > 32)
      return "refill lanes " + std::to_string(refill_lanes) + ": expected 1 to 32 (the lanes of a warp)";
    if (speed_every < 1 || (speed_every & (speed_every - 1)) != 0)
      return "signal speed interval " + std::to_string(speed_every) + " steps: expected a power of 2 (1, 2, 4, ...)";
    return {};
  }
};

}  // namespace scree
