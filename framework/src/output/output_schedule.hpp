// OutputSchedule: a case's writers and function objects, when each runs, and the thread
// they run on.
//
// Writers run at the write times of system/controlDict (writeControl, writeInterval).
// Each function object runs on its own executeControl: writeTime (with the writers),
// timeStep (every executeInterval steps) or runTime (every executeInterval seconds). The
// time loop asks for the next event (so that its chunk of steps ends on it and the clock
// lands on its time), asks what is due, hands a snapshot to submit() and reports done().
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "output_thread.hpp"
#include "scree/output/function_object.hpp"
#include "scree/output/snapshot.hpp"
#include "scree/output/writer.hpp"

namespace scree {

class OutputSchedule {
 public:
  /// A function object and its executeControl / executeInterval.
  struct Function {
    enum class Control { writeTime, timeStep, runTime };
    std::unique_ptr<FunctionObject> object;
    Control control = Control::writeTime;
    double interval = 1;  ///< steps or seconds
    bool reduces = false;  ///< it reduces over ranks (function_object.hpp)
  };
  /// The writers write every `write_interval` steps (by_steps) or seconds, from
  /// start_time on; each function object on its own control.
  OutputSchedule(std::vector<std::unique_ptr<Writer>> writers, std::vector<Function> functions, bool by_steps,
                 double write_interval, double start_time);
  ~OutputSchedule();  ///< waits for the output thread before the plugins die

  bool empty() const { return writers_.empty() && functions_.empty(); }
  bool wants_grid() const { return wants_grid_; }

  /// Tighten the next event after time t and step `step`: t_event (a time) and step_event
  /// (steps from now; -1: none).
  void next_event(double t, std::int64_t step, double& t_event, std::int64_t& step_event) const;

  /// What is due at time t and step `step` (everything when force_all).
  struct Due {
    bool write_time = false;            ///< a write time (with or without writers: checkpoints)
    bool write = false;                 ///< the writers
    std::vector<std::size_t> functions; ///< indices of function objects
    bool any() const { return write || !functions.empty(); }
    bool with_grid = false;             ///< a writer due wants the grid
  };
  Due due(double t, std::int64_t step, bool force_all) const;

  /// A run decomposed over several ranks: the writers that write pieces (Writer::writes_pieces)
  /// are driven by the solver on every rank, and submit() leaves them out.
  void set_decomposed() { decomposed_ = true; }
  /// The writers of pieces (in the case's order), for the solver to drive.
  std::vector<Writer*> piece_writers() const;
  /// Whether what is due needs the whole case on the root: a function object that does not
  /// reduce over ranks, or a writer that does not write pieces (every writer and function
  /// object in a run of one rank).
  bool gathers(const Due& d) const;
  /// Function object i when the run is decomposed and it reduces over ranks (the solver
  /// executes it on every rank, and submit() leaves it out), else null.
  FunctionObject* reducing(std::size_t i) const {
    return decomposed_ && reduces_[i] ? functions_[i].get() : nullptr;
  }

  /// Run what is due on the output thread. `finish[i]`, if given, completes body i of the
  /// snapshot there first (an asynchronous copy off the device).
  void submit(const Due& d, std::shared_ptr<Snapshot> snap,
              std::vector<std::function<void(BodySnapshot&)>> finish);
  /// Move the schedules of what ran past time t / step `step`.
  void done(const Due& d, double t, std::int64_t step);

  /// When the writers and each function object are due next, for a checkpoint (taken before
  /// done() of the write time it belongs to, so that a restart runs again what was due
  /// then), and its restoration. A case whose function objects changed since the
  /// checkpoint restores the writers' schedule only (returns false): its function objects
  /// start on their schedules at the restart time.
  std::vector<double> state() const;
  bool restore(const std::vector<double>& s);

  /// Run `job` on the output thread, after everything submitted before it.
  void submit_job(std::function<void()> job) { thread_->submit(std::move(job)); }
  void drain() { thread_->drain(); }
  /// Drain, then let every writer and function object finish (close series files).
  void finish();

 private:
  struct Scheduled {
    enum class Control { timeStep, runTime, writeTime } control = Control::writeTime;
    double interval = 0;
    double next_time = 0;
    std::int64_t next_step = 0;
  };
  void bump(Scheduled& s, double t, std::int64_t step) const;

  std::vector<std::unique_ptr<Writer>> writers_;
  std::vector<std::unique_ptr<FunctionObject>> functions_;
  std::vector<bool> reduces_;
  std::vector<Scheduled> function_schedule_;
  Scheduled write_schedule_;
  bool wants_grid_ = false;
  bool decomposed_ = false;
  std::unique_ptr<OutputThread> thread_;
};

}  // namespace scree
