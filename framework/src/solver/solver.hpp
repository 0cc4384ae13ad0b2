// Solver<D>: the explicit MPM time loop for one case (private to the core).
//
// A step of the explicit MPM (Feng et al. 2025, section 2.2): (a) P2G of mass and momentum,
// (b) nodal velocities with the boundary conditions, (c) the stress update at the points
// from the grid's velocity gradient, (d) internal and external nodal forces, (e) the nodal
// update of the velocities, (f) G2P of velocities and positions. Per step k (parity
// p = k % 2) the particle passes scatter into grid set B = sets[p] and gather from the
// previous step's set A = sets[1 - p]; the G2P of step k runs fused with the P2G of step
// k + 1 (the "pending" gather: fused_pass), or in flush() before output. The update
// schemes order the stages so:
//
//   USF  (the paper's order): pass[G2P_{k-1} | P2G m, mv] -> grid[v^k]
//                             -> pass[stress from v^k | P2G f] -> grid[v^{k+1}]
//   USL  (fused, one pass):   pass[G2P_{k-1}, stress from v^k_{new} | P2G m, mv, f]
//                             -> grid[v^k, v^{k+1}]
//   MUSL:                     pass[stress from remapped v, x update | P2G m, mv, f]
//                             -> grid[v^k, v^{k+1}] -> pass[v_p update | P2G m v_p]
//                             -> grid[remapped v]
//   two-phase (USL):          pore[G2P_{k-1} v_l, p_w] -> pass[as USL] -> pore[P2G liquid,
//                             pore force] -> two-phase grid[v_s, v_l; implicit drag]
//                             -> hydraulic laws (porous/two_phase.hpp)
//
// The clock lives on the device (time/step_control.hpp); the host syncs once per chunk of
// steps (to report progress, write output, or re-sort particles). On CUDA a chunk replays
// captured graphs of two steps. The pieces around the loop have their own units:
// TimeControl (time/), OutputSchedule (output/), KernelPolicy (exec/), SplitTuner,
// Progress, the case model (case/case_model.hpp); of Solver itself, solver_setup.cpp
// builds the grid, bodies, boundaries and output, passes.cpp the parameters of the
// passes and grid updates, solver_output.cpp writes output and checkpoints, health.cpp
// reports a failed run, and solver.cpp is the step and the loop.
#pragma once

#include <iosfwd>
#include <memory>
#include <new>
#include <optional>
#include <array>
#include <vector>

#include "../exec/pinned_buffer.hpp"
#include "../exec/step_graphs.hpp"
#include "../output/output_schedule.hpp"
#include "../porous/porous_media.hpp"
#include "progress.hpp"
#include "scree/boundary/boundary_condition.hpp"
#include "scree/case/case.hpp"
#include "scree/case/case_model.hpp"
#include "scree/case/checkpoint.hpp"
#include "scree/case/decomposition.hpp"
#include "scree/case/overburden.hpp"
#include "scree/comm/comm.hpp"
#include "scree/exec/kernel_policy.hpp"
#include "scree/exec/memory.hpp"
#include "scree/mpm/body.hpp"
#include "scree/mpm/grid_update.hpp"
#include "scree/mpm/halo_box.hpp"
#include "scree/plugin/context.hpp"
#include "scree/solver/simulation.hpp"
#include "scree/time/time_control.hpp"
#include "split_tuner.hpp"

namespace scree {

/// The G2P that finishes a step (and USL's stress update from its v^{k+1}): it runs fused
/// into the next step's first pass (Solver::fused_pass), or alone in Solver::flush.
inline unsigned g2p_of(UpdateScheme s) {
  switch (s) {
    case UpdateScheme::USL: return kGatherVelocity | kGatherPosition | kStressFromNew;
    case UpdateScheme::USF: return kGatherVelocity | kGatherPosition;
    case UpdateScheme::MUSL: return kStressFromVelocity | kGatherPosition;
  }
  return 0;
}

template <int D>
class Solver {
 public:
  Solver(const Case& c, PluginRuntime& rt, const RunOptions& o);
  ~Solver();

  RunStats run();
  void advance_to(double t, bool with_output);
  void run_steps(std::int64_t n);
  /// Every body (and the grid): a decomposed run's whole case, on its root rank (collective).
  Snapshot snapshot(bool with_grid);
  /// This rank's part of it. The case's sums over the ranks (the liquid's inflow totals)
  /// are summed with the other ranks (collective) unless `alone` (a diagnosis of one rank:
  /// this rank's share).
  Snapshot local_snapshot(bool with_grid, bool alone = false);
  void set_velocities(std::size_t body, const std::vector<Real>& v);
  double time() const { return host_ctl_.t[parity()]; }
  std::int64_t steps() const { return step_; }
  RunStats stats() const;

 private:
  // setup (solver_setup.cpp)
  void setup_streams();
  void setup_grid();
  /// The two grid sets (and their tile stamps) of grid_, and the plugins' context of it.
  void allocate_grid();
  void setup_bodies();
  /// One body of constant/bodies: its particles generated, its material's body made.
  /// `overburden`: every body's columns, for a geostatic stress from the material above.
  void setup_body(const Entry& e, int& id, std::int64_t& next_id, Real& min_mass, const Overburden<D>* overburden);
  /// The initial density of a body's material [kg/m^3] (a two-phase body's: the grains').
  Real body_density(const Dictionary& b) const;
  /// The error for an allocation of part `part` of the memory estimate (0: the grid, then
  /// the bodies) that failed: its entry, its size (memory_estimate.hpp) and `e`.
  InputError out_of_memory(std::size_t part, const std::bad_alloc& e) const;
  void setup_boundaries(bool warn = true);
  void setup_split();
  void setup_output();
  /// What every particle pass and grid update of the run shares (the physics of the case
  /// and the kernel policy), once the grid, bodies, walls and output are set up (passes.cpp).
  void setup_passes();
  /// Continue from a checkpoint (opt_.restart): the bodies', liquid's, clock's and
  /// schedules' state, checked against the case.
  void restore(const Checkpoint& ck);

  // the step
  void step();                        ///< launch one step (all its passes and grid updates)
  void step_two_phase();              ///< ... of a case with two-phase bodies (USL)
  void launch_steps(std::int64_t n);  ///< n steps, via CUDA graphs when possible
  void flush();                       ///< apply the pending gather (G2P) of the last step
  /// The pass that opens a step: the last step's pending G2P fused with this step's P2G
  /// phases `p2g` (the fusion of the update schemes, said here once).
  PassParams<D> fused_pass(unsigned p2g) const;
  /// A pass that gathers from and scatters into this step's grid set.
  PassParams<D> this_step_pass(unsigned phases) const;
  /// pass_physics_ and pass_policy_ with the phases `flags`, the grid sets and the parity of the step gathered from.
  PassParams<D> pass_params(unsigned flags, int gather_set, int scatter_set, int gather_parity) const;
  GridUpdateParams<D> grid_params(unsigned modes, int set) const;
  void apply_node_laws(unsigned modes, int set) const;
  template <class F>
  void phase(const char* name, F&& f);  ///< run f as phase `name` (timed with --profile)

  // the loop
  void advance_chunked(double target, std::int64_t step_limit, bool with_output);
  void run_chunk(std::int64_t n);
  void after_chunk(bool with_output);
  void check_health();        ///< throws RunFailure when the device stopped the clock on a failure
  std::string diagnosis();    ///< what went wrong, which particle, body, material, field, step (health.cpp)
  /// Whether output_due writes a checkpoint: on every checkpointInterval-th write time
  /// (scheduled), with these writes whatever the time (always: endTime, a signal), or not
  /// (never: the state a failed run stopped in is written for the diagnosis, and the newest
  /// checkpoint stays the last healthy write time, to restart from).
  enum class CheckpointWhen { scheduled, always, never };
  /// Write what is due now (everything when force_all), with a checkpoint as `checkpoint` says.
  void output_due(bool force_all, CheckpointWhen checkpoint = CheckpointWhen::scheduled);
  /// The checkpoint of now, queued on the output thread after the writes of now (a
  /// killed run then has the frames of a checkpoint's time written before the checkpoint).
  void write_checkpoint(const std::vector<double>& schedule);
  /// output_due of a decomposed run: what the root found due, written on the root from
  /// every rank's part (decomposed.cpp gathers it).
  void output_ranks(const OutputSchedule::Due& due, bool checkpoint, const std::vector<double>& schedule);
  /// Write every writer's output of now (and a checkpoint when asked), wait for the
  /// output thread.
  void finish_output(CheckpointWhen checkpoint);
  Snapshot snapshot_header() const;  ///< time, step and the bodies' material names
  /// The stress pass's way (SplitTuner): 0 whole, 1 split, 2 split with the deferred
  /// updates in turns.
  int stress_way() const { return split_ ? (refill_ ? 2 : 1) : 0; }
  void set_stress_way(int way);
  Real max_signal_speed() const;

  // a decomposed run (decomposed.cpp): what the ranks exchange and agree on
  bool decomposed() const { return comm_->size() > 1; }
  bool root() const { return comm_->rank() == 0; }
  /// Cut the grid into boxes from the points the bodies will have (counted alike on every
  /// rank, not made) and set up this rank's grid; setup_body then makes only the points of
  /// this rank's box, so no rank holds more of the case than its own part.
  void decompose_case();
  /// Refuse, on every rank and before anything of the boxes is allocated, a decomposition
  /// in which a rank's grid and points (`per_body`: each body's points in each rank's box,
  /// and each body's total) would not fit in its backend's free memory, naming that rank
  /// and its box.
  void check_rank_memory(const std::vector<std::vector<std::uint64_t>>& per_body,
                         const std::vector<std::uint64_t>& totals) const;
  /// Log how the grid was cut and the points each rank holds.
  void report_decomposition();
  /// Log, per body whose material bounds its stress update's work (Body::work_bound), how
  /// many updates reached that bound in this run, over every rank (collective).
  void report_bounded_updates();
  /// Make decomp_'s box this rank's grid: its geometry, its grid sets (the pore liquid's
  /// too), the plugins' context.
  void set_local_grid();
  /// The pore liquid's halo sums, through this rank's (PorousMedia::set_halo).
  void set_porous_halo();
  /// Take up the boxes `d` (a rebalance, a restart's): this rank's grid, the boundary
  /// conditions' nodes on it and the passes' parameters set up anew.
  void adopt(Decomposition<D> d);
  /// Move to the boxes of recut_ (a rebalance): the pending G2P applied, this rank's grid
  /// and the boundary conditions' nodes set up anew; the points then migrate.
  void apply_recut();
  /// The points of `block` (a body's block of n points) that this rank's box holds.
  std::vector<Real> keep_own(const std::vector<Real>& block, Index n, Index& kept) const;
  /// Before a grid update of set `set`: the halo sum of what the passes since the last
  /// one scattered (scattered_), and, before the update that advances the clock, the
  /// reduction of the clock's inputs over the ranks.
  void exchange_before_grid(int set, unsigned modes);
  void halo_sum(int set, unsigned scattered);
  /// The halo sum of any nodal fields (grid-sized arrays of this rank's grid, cells
  /// indexed as nodes included): the pore liquid's sums (PorousMedia::set_halo) as the
  /// solid's.
  void halo_exchange(const HaloFields& fields);
  /// Whether the halo's messages go from and into the backend's memory as they are (the
  /// CPU backend, or an MPI that can read GPU memory: Comm::device_aware), not through
  /// host buffers.
  bool halo_direct() const;
  /// The nodes whose shares this rank adds to the case's sums: its own box's (all on one rank).
  OwnedNodes<D> owned_nodes() const;
  /// The pore liquid's cumulative inflows over the ranks (PorousMedia::totals), for a
  /// snapshot or a checkpoint.
  std::vector<Real> liquid_totals() const;
  void reduce_clock();
  /// One agreement per chunk: the root's length n (its output schedule and wall clock)
  /// and target, no longer than the points may move before they migrate again.
  void agree_chunk(std::int64_t& n, double& t_event);
  /// A stop requested of any rank (a signal).
  int agree_signal();
  /// check_health of a decomposed run: a failure of any rank (one found in a chunk's last
  /// step is known only to its rank yet) stops every rank, with the diagnosis of the first
  /// rank that found one.
  void check_health_ranks();
  /// Every point to the rank whose box holds it; the step of the next migration from the
  /// fastest point (the halo's slack); whether the cuts should move. A `scheduled` one (at
  /// its step, not at a write time or a restart, whose times do not depend on the cuts)
  /// first moves the cuts a migration before decided (recut_), so that a restarted run
  /// moves them at the steps the uninterrupted one did.
  void migrate(bool scheduled = true);
  /// The longest chunk of steps in which no point moves more than the halo's slack.
  std::int64_t migration_steps() const;
  /// The whole snapshot on the root rank (each rank's points; the grid's owned nodes).
  void gather_snapshot(Snapshot& s);
  /// The writers of pieces at a write time (Writer::begin_frame, write_piece): every rank
  /// writes the points it holds; returns the frames, in the order of piece_writers_, once
  /// every rank's piece is in place.
  std::vector<std::string> write_pieces(const Snapshot& local);
  /// A collective: when any rank's `error` is not empty, every rank throws the first such
  /// rank's, named by its rank.
  void agree_error(const std::string& error);
  /// The clock of a checkpoint over the ranks: the lost points and the energy ledger
  /// summed, the signal speed the largest.
  void reduce_checkpoint_clock(Checkpoint& ck);
  void gather_grid(Snapshot& s);
  void sync_control_from_device();
  void sync_control_to_device();
  int parity() const { return static_cast<int>(step_ % 2); }
  /// Steps that advanced the clock (dt > 0), as of the last sync with the device.
  std::int64_t steps_done() const { return static_cast<std::int64_t>(host_ctl_.steps_done); }

  const Case& case_;
  const CaseSettings& settings_;
  PluginRuntime& rt_;
  RunOptions opt_;
  const KernelPolicy& policy_ = opt_.kernels;
  std::ostream& log_;
  Exec exec_;
  SolverContext ctx_;
  void* stream_ = nullptr;       // cudaStream_t of the steps
  void* copy_stream_ = nullptr;  // snapshots' transfers to the host, beside the steps

  // Ranks (comm/comm.hpp) and this rank's part of the case (case/decomposition.hpp)
  std::shared_ptr<Comm> comm_;
  Decomposition<D> decomp_;
  GlobalGrid<D> global_{};           // the whole grid (grid_: this rank's part, the same on one rank)
  unsigned scattered_ = 0;           // what the passes since the last grid update scattered
  std::uint64_t lost_stop_global_ = 0;  // StepControl::lost_stop over every rank's points
  double vmax_ = 0;                  // the fastest point at the last migration [m/s]
  std::int64_t migration_limit_ = 0; // the steps from one migration to the next
  std::int64_t next_migration_ = 0;  // steps_done() at which the points migrate next (as sorts, not on wall time)
  std::int64_t migrations_ = 0;
  bool migrated_ = false;            // the points migrated at this chunk's end already (output_due)
  std::vector<std::uint64_t> body_totals_;  // each body's points over every rank
  std::optional<Decomposition<D>> recut_;   // the boxes the next migration moves to (a rebalance)
  std::int64_t rebalances_ = 0;
  std::vector<HaloPeer<D>> halo_peers_;  // the boxes shared with each neighbour (decomp_.neighbours)
  Buffer<HaloPeer<D>> halo_peers_dev_;   // ... on the backend
  int halo_self_ = 0;                    // the neighbours of lower rank than this one
  Buffer<Real> halo_buffer_;             // the shared boxes packed on the backend
  Buffer<Real> halo_arrived_;            // ... the neighbours' boxes, received on the backend (halo_direct)
  PinnedBuffer<Real> halo_send_, halo_recv_;  // ... or their host copies, sent and received

  // Algorithm (system/mpmSchemes, constant/g)
  Vec<D> gravity_;
  Real mass_eps_ = 0;  // nodes lighter than this are not accelerated [kg]
  std::int64_t sort_interval_ = 0;
  std::int64_t sorted_at_ = 0;  // steps_done() at the last sort

  // Grid and boundary conditions
  GlobalGrid<D> grid_{};
  Buffer<Real> grid_data_[2];
  GridFields<D> sets_[2]{};
  mutable Buffer<std::uint32_t> tile_stamps_[2];  // sparse grid updates: tiles each set's passes touched
  Buffer<Wall> walls_;                       // the walls, applied in the grid update
  Buffer<WallMask> masks_;                   // per node: the walls acting on it
  bool has_walls_ = false;
  std::vector<std::unique_ptr<BoundaryCondition>> boundaries_;
  std::vector<const BoundaryCondition*> node_laws_;  // those with a node law of their own

  // Particles
  std::vector<std::unique_ptr<Body<D>>> bodies_;
  std::vector<std::string> material_names_;  // each body's material (constant/materialProperties)
  std::unique_ptr<PorousMedia<D>> porous_;   // the pore liquid of two-phase bodies (none: single phase)

  // Time
  TimeControl time_;
  mutable Buffer<StepControl> ctl_;  // the clock on the device (kernels write it)
  StepControl host_ctl_{};           // its host copy, synced once per chunk
  std::int64_t step_ = 0;
  bool pending_ = false;             // the last step's gather has not run yet
  bool lost_warned_ = false;         // particles leaving the grid already reported

  // Kernels
  bool energy_ledger_ = false;       // a function object asked for the energy ledger (StepControl::energy)
  bool split_ = false, can_split_ = false;
  bool refill_ = false, can_refill_ = false;  // the split's deferred updates in turns (KernelPolicy::refill)
  std::optional<SplitTuner> tuner_;  // KernelPolicy::split automatic, on CUDA
  std::int64_t split_steps_ = 0;     // steps run split
  std::int64_t refill_steps_ = 0;    // ... of which with the deferred updates in turns
  std::unique_ptr<StepGraphs> graphs_;
  PassPhysics<D> pass_physics_{};    // every pass's physics (setup_passes)
  PassPolicy pass_policy_{};          // every pass's kernel policy (setup_passes; pass_params adds the way)
  GridUpdateParams<D> grid_base_{};   // every grid update's (setup_passes)

  // Output, progress and statistics
  std::unique_ptr<OutputSchedule> output_;
  // A decomposed run's writers of pieces (Writer::writes_pieces): the root's are in output_,
  // the other ranks own theirs.
  std::vector<Writer*> piece_writers_;
  std::vector<std::unique_ptr<Writer>> own_piece_writers_;
  // A decomposed run's function objects that reduce over ranks, executed on every rank
  // (output/function_object.hpp): by the case's order of function objects, null for one
  // that runs on the root alone. The root's are in output_, the other ranks own theirs.
  std::vector<FunctionObject*> rank_functions_;
  std::vector<std::unique_ptr<FunctionObject>> own_functions_;
  std::int64_t writes_ = 0;          // write times since startTime (the first not counted)
  bool first_output_ = true;         // the run's first output (the initial or restart state)
  double checkpoint_time_ = -1;      // the time of the last checkpoint this run wrote
  // The output schedule as it was before the scheduled output of step due_step_ (output_due):
  // a checkpoint forced at that same step (a signal, endTime) stores it, so that a restart
  // from it writes again what was due then (its CSVs and series keep only what came before).
  std::vector<double> due_schedule_;
  std::int64_t due_step_ = -1;
  double run_start_ = 0;             // startTime, or the time of the checkpoint restarted from
  std::int64_t first_step_ = 0;      // the step this process's run() started at
  Progress progress_;
  PhaseProfile profile_;
  double wall_ = 0, output_wall_ = 0;
  double chunk_rate_ = 0;  // steps per second, measured
};

// Defined here: the stages in solver.cpp and the ranks' exchanges in decomposed.cpp time
// their phases alike.
template <int D>
template <class F>
void Solver<D>::phase(const char* name, F&& f) {
  if (!opt_.profile) {
    f();
    return;
  }
  mem::synchronize(exec_.device);
  const auto t0 = std::chrono::steady_clock::now();
  f();
  mem::synchronize(exec_.device);
  profile_.add(name, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
}

}  // namespace scree
