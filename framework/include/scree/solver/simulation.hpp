// Running a case: the time loop, output scheduling and progress.
//
//   PluginRuntime rt;  rt.load_default_plugins();
//   Case c = Case::read("cases/columnCollapse", rt);
//   Simulation sim(c, rt, RunOptions{});
//   sim.run();                 // to endTime, writing output and running function objects
//
// Tests and tools can also step a case themselves (advance_to, snapshot).
#pragma once

#include <cstdint>
#include <filesystem>
#include <iosfwd>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "scree/case/case.hpp"
#include "scree/comm/comm.hpp"
#include "scree/exec/kernel_policy.hpp"
#include "scree/exec/memory.hpp"
#include "scree/output/snapshot.hpp"
#include "scree/plugin/loader.hpp"

namespace scree {

/// A run that went wrong (a non-finite field, particles leaving the grid en masse, an
/// unstable step: time/step_control.hpp) and was stopped; what() is the diagnosis. The
/// state it stopped in has been written by the case's writers (Simulation::run).
class SCREE_API RunFailure : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A run stopped on request (request_stop: scree's SIGINT/SIGTERM handler) at the end of a
/// chunk of steps, its state written (Simulation::run); `signal` is the request's number.
class SCREE_API RunInterrupted : public std::runtime_error {
 public:
  RunInterrupted(const std::string& what, int signal) : std::runtime_error(what), signal_(signal) {}
  int signal() const noexcept { return signal_; }

 private:
  int signal_;
};

/// Ask a running Simulation to stop after its current chunk of steps (at most about 0.5 s
/// of wall time): async-signal-safe (a lock-free atomic store), for a signal handler.
/// `signal` is reported in RunInterrupted; 0 clears the request.
SCREE_API void request_stop(int signal) noexcept;
/// The pending request's signal number, or 0.
SCREE_API int stop_requested() noexcept;

struct RunOptions {
  Device device = Device::cpu;
  int threads = 1;             ///< CPU threads (OpenMP)
  bool output = true;          ///< writers and function objects (off for benchmarks)
  /// Keep the energy ledger (StepControl::energy, in every Snapshot) even when no function
  /// object asks for it (tests; benchmarks of its cost).
  bool energy_ledger = false;
  std::int64_t max_steps = -1; ///< stop after this many steps (benchmarks); -1: no limit
  bool progress = true;        ///< progress line on stdout
  bool profile = false;        ///< time every kernel phase (synchronising; no graphs) and report
  /// How the kernels run (exec/kernel_policy.hpp): the fast kernels by default.
  KernelPolicy kernels;
  std::ostream* log = nullptr; ///< messages (default std::cout)
  /// Run check_setup (setup_check.hpp) first: every problem of the setup is then thrown
  /// together as InputErrors before anything is allocated or written, and its warnings
  /// go to `log`. Off only for a caller that ran it itself (the scree executable).
  bool check_setup = true;
  /// A checkpoint to continue from (case/checkpoint.hpp; empty: start from the case's
  /// initial state). The writers and function objects continue their series from its time.
  std::filesystem::path restart;
  /// With `restart`: continue although the case's physics changed since the checkpoint was
  /// written (case_physics: the changed entries are listed as a warning). Off, such a
  /// restart is refused, listing them.
  bool accept_changes = false;
  /// The ranks the case is decomposed over (comm/comm.hpp; case/decomposition.hpp): null
  /// takes world(), every rank of an MPI run (one rank without MPI); self() runs this
  /// process's case alone.
  std::shared_ptr<Comm> comm;
};

struct RunStats {
  std::int64_t split_steps = 0;  ///< steps whose stress pass ran split (KernelPolicy::split)
  std::int64_t refill_steps = 0;  ///< ... of which with the deferred updates in turns (KernelPolicy::refill)
  std::int64_t steps = 0;      ///< the steps this process took (a restart: since the checkpoint)
  std::int64_t last_step = 0;  ///< the step number reached, counted from the run's start
  double simulated_time = 0;   ///< [s] simulated by this process
  double wall_seconds = 0;     ///< wall time of the steps (the chunks of steps), setup and output excluded [s]
  double output_seconds = 0;   ///< wall time the loop spent taking snapshots and handing them to the output
                               ///< thread, besides wall_seconds [s]
  std::int64_t particles = 0;
  std::int64_t nodes = 0;
  std::size_t bytes_per_particle = 0;
  std::size_t peak_device_bytes = 0;
  std::uint64_t lost_particles = 0;
  std::int64_t rebalances = 0;   ///< a decomposed run: the times its cuts moved with the mass
};

class SCREE_API Simulation {
 public:
  Simulation(const Case& c, PluginRuntime& rt, const RunOptions& options);
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  int dimension() const;
  /// Run to endTime with output; returns the statistics.
  RunStats run();
  /// Advance to time t (no output unless `with_output`).
  void advance_to(double t, bool with_output = false);
  /// Run exactly n steps (no output).
  void run_steps(std::int64_t n);
  /// A host copy of every body (pending particle updates are applied first).
  Snapshot snapshot(bool with_grid = false);
  /// Set the velocities of body `body` (index in constant/bodies) before the first step:
  /// dimension() values per particle, in the order of snapshot().bodies[body].
  void set_velocities(std::size_t body, const std::vector<double>& v);
  double time() const;
  std::int64_t steps() const;
  RunStats stats() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace scree
