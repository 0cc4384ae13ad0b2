// Function-object plugins (OpenFOAM's term): run-time post-processing such as a run-out
// tracker or particle probes. Each runs at its own interval (`executeControl timeStep |
// runTime`, `executeInterval`, declared by the core for every function object) on a
// host Snapshot, and writes under <case>/postProcessing/<name>/.
//
// Long runs never lose finished results: write and flush each row as it is produced
// (or rewrite files atomically), so a killed run keeps everything up to its last row.
// Nor does a second run: `scree` does not start over a non-empty postProcessing/<name>/
// of the case unless given --overwrite (case/setup_check.hpp).
//
//   struct MyFO : FunctionObject {
//     static constexpr const char* type_name = "myFO";
//     static ParamSpec spec();
//     MyFO(const ParamReader& r, const SolverContext& ctx);
//     void execute(const Snapshot& s) override;
//   };
//   SCREE_PLUGIN(r) { r.add_function_object<MyFO>(); }
//
// Several ranks (a decomposed run, docs/multi-gpu.md). By default a function object runs on
// rank 0 with the whole case gathered there, its points in the order of their ids: simple,
// but rank 0's host then holds every point. One that declares
//
//     static constexpr bool reduces_over_ranks = true;
//
// is made on every rank (SolverContext::comm names them) and executed on every rank, in
// the main thread, with the points that rank holds (in no particular order; the energy
// ledger and the per-body scalars are the case's). It combines what it measures with
// Ranks (output/ranks.hpp: sums, maxima, quantiles, a gather), every rank making the same
// calls in the same order, and only Ranks::root() writes files. On one rank the same code
// runs on the output thread with the whole case, and each Ranks call is its argument.
#pragma once

#include "scree/output/snapshot.hpp"
#include "scree/params/spec.hpp"

namespace scree {

struct SolverContext;  // what plugins learn about the case (scree/plugin/context.hpp)

class SCREE_API FunctionObject {
 public:
  virtual ~FunctionObject();
  virtual void execute(const Snapshot& s) = 0;
  virtual void finish() {}
  /// Whether the kernels should keep the energy ledger for it (StepControl::energy, in
  /// Snapshot::energy): the stress work and the losses that no snapshot can show. Asked once,
  /// after construction; keeping it costs the kernels a little (energies' `budget`).
  virtual bool needs_energy_ledger() const { return false; }
};

}  // namespace scree
