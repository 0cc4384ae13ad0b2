// Solver<D>: the explicit MPM time loop for one case (private to the core).
//
// Per step k (parity p = k % 2) the particle passes scatter into grid set B = sets[p]
// and gather from the previous step's set A = sets[1 - p]; the G2P of step k runs fused
// with the P2G of step k + 1 (the "pending" gather), or in flush() before output.
//
//   USF  (the paper's order): pass[G2P_{k-1} | P2G m, mv] -> grid[v^k]
//                             -> pass[stress from v^k | P2G f] -> grid[v^{k+1}]
//   USL  (fused, one pass):   pass[G2P_{k-1}, stress from v^k_{new} | P2G m, mv, f]
//                             -> grid[v^k, v^{k+1}]
//   MUSL:                     pass[stress from remapped v, x update | P2G m, mv, f]
//                             -> grid[v^k, v^{k+1}] -> pass[v_p update | P2G m v_p]
//                             -> grid[remapped v]
//
// Time control lives on the device (StepControl); the host syncs once per chunk of steps
// (to report progress, write output, or re-sort particles). On CUDA a chunk replays a
// captured graph of two steps.
#pragma once

#include <chrono>
#include <condition_variable>
#include <deque>
#include <exception>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <ostream>
#include <thread>
#include <vector>

#include "scree/boundary/boundary_condition.hpp"
#include "scree/exec/memory.hpp"
#include "scree/mpm/body.hpp"
#include "scree/mpm/grid_update.hpp"
#include "scree/output/function_object.hpp"
#include "scree/output/writer.hpp"
#include "scree/solver/case.hpp"
#include "scree/solver/simulation.hpp"

namespace scree {

enum class UpdateScheme { USF, USL, MUSL };

/// Runs writers and function objects on a thread of their own, one snapshot at a time.
class OutputThread {
 public:
  using Job = std::function<void()>;
  OutputThread();
  ~OutputThread();
  /// Queue a job; waits while one job is already waiting (bounded memory).
  void submit(Job job);
  /// Wait until the queue is empty; rethrow the first error of a job.
  void drain();

 private:
  void loop();
  std::mutex m_;
  std::condition_variable cv_;
  std::deque<Job> jobs_;
  bool stop_ = false, busy_ = false;
  std::exception_ptr error_;
  std::thread thread_;
};

template <int D>
class Solver {
 public:
  Solver(const Case& c, PluginRuntime& rt, const RunOptions& o);
  ~Solver();

  RunStats run();
  void advance_to(double t, bool with_output);
  void run_steps(std::int64_t n);
  Snapshot snapshot(bool with_grid);
  Snapshot snapshot_header() const;  ///< time, step and the bodies' material names
  void set_velocities(std::size_t body, const std::vector<Real>& v);
  double time() const { return host_ctl_.t[step_ % 2]; }
  std::int64_t steps() const { return step_; }
  RunStats stats() const;

 private:
  struct Scheduled {  // a writer or function object and when it runs
    enum class Control { timeStep, runTime, writeTime } control = Control::writeTime;
    double interval = 0;
    double next_time = 0;
    std::int64_t next_step = 0;
  };

  void setup_grid();
  void setup_bodies();
  void setup_boundaries();
  void setup_output();
  void setup_time();

  void step();                      ///< launch one step (all its passes and grid updates)
  void launch_steps(std::int64_t n);  ///< n steps, via CUDA graphs when possible
  void flush();                     ///< apply the pending gather (G2P) of the last step
  void sync_control_from_device();
  void sync_control_to_device();
  void advance_chunked(double target, std::int64_t step_limit, bool with_output);
  void output_due(bool force_all);
  void report_progress(bool final);
  void check_time_step();
  void watch_time_step();
  PassParams<D> pass_params(unsigned flags, int gather_set, int scatter_set, int gather_parity) const;
  GridUpdateParams<D> grid_params(unsigned modes, int set) const;
  void destroy_graphs();
  void tune_split(std::int64_t n, double seconds);
  void set_split(bool on);
  /// Run `f` as phase `name`; with profiling on, synchronise and accumulate its time.
  template <class F>
  void phase(const char* name, F&& f);
  void report_profile();

  const Case& case_;
  PluginRuntime& rt_;
  RunOptions opt_;
  std::ostream& log_;
  Exec exec_;
  SolverContext ctx_;

  // Algorithm
  UpdateScheme scheme_ = UpdateScheme::USF;
  ShapeKind shape_ = ShapeKind::linear;
  Transfer transfer_ = Transfer::flip;
  Real pic_fraction_ = 0;
  Real max_volume_ratio_ = std::numeric_limits<Real>::infinity();  ///< mpmSchemes maxVolumeRatio
  Real damping_ = 0, damping_start_ = 0, damping_end_ = 0;
  Real mass_tolerance_ = 1e-6, mass_eps_ = 0;
  std::int64_t sort_interval_ = 0;
  Vec<D> gravity_;

  // Grid
  GridGeometry<D> grid_{};
  Buffer<Real> grid_data_[2];
  GridFields<D> sets_[2]{};
  mutable Buffer<std::uint32_t> tile_stamps_[2];  // sparse grid updates: tiles each set's passes touched
  bool sparse_ = false;
  Buffer<Constraint> constraints_;
  Buffer<ConstraintMask> masks_;
  bool has_constraints_ = false;

  // Particles
  std::vector<std::unique_ptr<Body<D>>> bodies_;

  // Time control
  mutable Buffer<StepControl> ctl_;  // device time control (kernels write it)
  StepControl host_ctl_{};
  std::int64_t step_ = 0;
  bool pending_ = false;
  double start_time_ = 0, end_time_ = 0, delta_t_ = 0;
  bool adaptive_ = false;
  bool dt_warned_ = false;        // the fixed step already reported as unstable
  bool lost_warned_ = false;      // particles leaving the grid already reported
  double dt_watch_wall_ = 0;      // wall_ at the last stability watch (fixed steps)

  // Output
  std::vector<std::unique_ptr<BoundaryCondition>> boundaries_;
  std::vector<std::unique_ptr<Writer>> writers_;
  std::vector<std::unique_ptr<FunctionObject>> functions_;
  std::vector<Scheduled> function_schedule_;
  Scheduled write_schedule_;
  std::unique_ptr<OutputThread> output_thread_;
  bool writers_want_grid_ = false;

  // Elastic-first split of the stress pass (RunOptions::split_elastic): on or off now, and
  // for `automatic` on CUDA the tuner that times both ways now and then and keeps the faster.
  bool split_ = false, can_split_ = false;
  struct SplitTuner {
    bool active = false;          // automatic, on CUDA, with a body that can split
    bool trial = false;           // this chunk runs the other way, to time it
    double rate[2] = {0, 0};      // steps per second, last measured split off [0] and on [1]
    double next_trial_wall = 0;   // wall_ at which the next trial starts
  } tuner_;
  std::int64_t split_steps_ = 0;  // steps run split

  // CUDA graphs (two steps each, starting at parity 0 and 1)
  void* graphs_[2] = {nullptr, nullptr};
  void* stream_ = nullptr;
  void* copy_stream_ = nullptr;  // snapshots' transfers to the host, beside the steps

  // Progress and statistics
  std::chrono::steady_clock::time_point run_start_, last_report_;
  std::int64_t progress_interval_ = 0;
  double wall_ = 0, output_wall_ = 0;
  double chunk_rate_ = 0;  // steps per second, measured
  bool tty_ = false;
  std::vector<std::pair<std::string, double>> profile_;  // phase name -> seconds
};

}  // namespace scree
