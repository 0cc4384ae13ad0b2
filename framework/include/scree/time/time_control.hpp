// Time control on the host: the first step, a new target time, the chunk of steps to
// reach it, and the watch over a fixed step. The per-step rules that run on the device
// (the CFL step, landing on the target) are in step_control.hpp; this class uses the same
// functions, so each rule is written once.
//
//   fixed step:    dt = deltaT; warned once (not changed) when it exceeds h / c
//   adaptive step: dt = min(maxDeltaT, maxCo h / (c + |v|)_max) after every step, and
//                  min(deltaT, maxCo h / c) for the first one
// with c the largest signal speed of any material point (Material::wave_speed).
#pragma once

#include <cstdint>
#include <functional>
#include <iosfwd>
#include <string>

#include "scree/core/config.hpp"
#include "scree/time/step_control.hpp"

namespace scree {

/// The time keys of system/controlDict.
struct TimeSettings {
  double start_time = 0;          ///< startTime [s]
  double end_time = 0;            ///< endTime [s]
  double delta_t = 0;             ///< deltaT [s]: the step, or the first one when adaptive
  bool adjust_time_step = false;  ///< adjustTimeStep
  double max_co = 0;              ///< maxCo: CFL number of the adaptive step [-]
  double max_delta_t = 0;         ///< maxDeltaT [s] (deltaT when not given)
  double stop_co = 0;             ///< stopCo: a fixed step of a larger Courant number stops the run (0: never)
};

class SCREE_API TimeControl {
 public:
  /// The largest signal speed c + |v| over the material points now [m/s].
  using SignalSpeed = std::function<Real()>;

  /// Throws std::invalid_argument when step_problem() finds the settings unusable (a
  /// validated case never is: Case::read reports it with the key's file:line).
  TimeControl(const TimeSettings& s, Real cell_size);

  /// The most steps a run may take from startTime to endTime at its largest step.
  /// Beyond it (a) the run cannot end in any useful time: 1e12 steps are more than three
  /// months even at 1e5 steps a second; and (b) the
  /// clock itself degrades: every t += dt is rounded by up to half an ulp of t, about
  /// 1.1e-16 endTime, which at 1e12 steps is 1e-4 of each step, so that the time a step
  /// reports drifts from the steps taken.
  static constexpr double kMaxSteps = 1e12;

  /// Why a run from `start_time` to `end_time` with steps of at most `max_step` cannot
  /// work, or "" when it can: the step is too small for the clock to advance at end_time
  /// (t + dt == t in double precision: the run would never end), or the run would need
  /// more than kMaxSteps steps. The text says what is valid: the smallest usable step.
  static std::string step_problem(double start_time, double end_time, double max_step);

  /// The clock at the start: t = startTime, dt = deltaT, aimed at endTime.
  StepControl initial() const;
  bool adaptive() const { return s_.adjust_time_step; }
  double start_time() const { return s_.start_time; }
  double end_time() const { return s_.end_time; }

  /// Before the first step, with the signal speed of the initial state: the adaptive step
  /// starts at min(deltaT, maxCo h / c); a fixed deltaT above h / c is reported to `log`.
  /// Returns whether ctl changed (the device copy must then be updated).
  bool start(StepControl& ctl, Real max_signal_speed, std::ostream& log);

  /// Whether t has reached `target` (within round-off).
  static bool reached(double t, double target);

  /// Steps from slot p's time to `target` at slot p's step (one more when adaptive, whose
  /// step may shrink), at least 1.
  std::int64_t steps_to(const StepControl& ctl, int p, double target) const;

  /// The steps of the next chunk (the host syncs with the device after each): those to
  /// the next event (steps_to `t_event`; `step_event` steps, if > 0), at most `budget`
  /// (if > 0) and `report` steps (a progress report, a particle sort), at least 1.
  std::int64_t chunk_length(const StepControl& ctl, int p, double t_event, std::int64_t step_event,
                            std::int64_t budget, std::int64_t report) const;

  /// Aim the clock at a new target: slot p's step is derived again (it may have been
  /// clamped to 0 on the old target) and clamped to land on the new one. Returns whether
  /// ctl changed.
  bool retarget(StepControl& ctl, int p, double target) const;

  /// A fixed step that was stable at the start may not stay so: the granular models stiffen
  /// with pressure and density, and an impact can raise p tenfold. Every 5 s of wall time
  /// the signal speed is measured again (a copy of the particle state to the host:
  /// milliseconds), and the first time deltaT exceeds h / c the user is told when, and
  /// what to do, before the run blows up.
  void watch(double wall_seconds, double t, std::int64_t step, const SignalSpeed& speed, std::ostream& log);

 private:
  TimeSettings s_;
  Real h_;
  bool warned_ = false;      // the fixed step already reported as unstable
  double watch_wall_ = 0;    // wall time at the last watch
};

}  // namespace scree
