// TimeControl (see time_control.hpp).
#include "scree/time/time_control.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ostream>
#include <stdexcept>
#include <string>

namespace scree {

namespace {
std::string seconds_text(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g s", v);
  return buf;
}
}  // namespace

TimeControl::TimeControl(const TimeSettings& s, Real cell_size) : s_(s), h_(cell_size) {
  const std::string problem =
      step_problem(s.start_time, s.end_time, s.adjust_time_step ? s.max_delta_t : s.delta_t);
  if (!problem.empty()) throw std::invalid_argument("time step: " + problem);
}

std::string TimeControl::step_problem(double start_time, double end_time, double max_step) {
  if (!(max_step > 0) || !(end_time > start_time)) return {};  // the specs' ranges report these
  const double span = end_time - start_time;
  // The smallest step that stays within kMaxSteps and that the clock can add at endTime.
  double smallest = span / kMaxSteps;
  const double t = std::max(std::fabs(start_time), std::fabs(end_time));
  const double half_ulp = 0.5 * (std::nextafter(t, HUGE_VAL) - t);
  smallest = std::max(smallest, 2 * half_ulp);
  const std::string valid = "; expected a step of at least " + seconds_text(smallest) +
                            " (at most 1e12 steps from startTime to endTime)";
  if (end_time + max_step == end_time || start_time + max_step == start_time)
    return "a step of " + seconds_text(max_step) + " cannot advance the clock: at t = " +
           seconds_text(start_time + max_step == start_time ? start_time : end_time) +
           ", t + " + seconds_text(max_step) + " rounds back to t in double precision, so the run would never end" +
           valid;
  const double steps = span / max_step;
  if (steps > kMaxSteps) {
    char n[32];
    std::snprintf(n, sizeof n, "%.3g", steps);
    return "a step of " + seconds_text(max_step) + " needs " + n + " steps to reach endTime " + seconds_text(end_time) +
           ", more than the limit of 1e12 (months of wall time, and a clock that can no longer add the step "
           "exactly)" + valid;
  }
  return {};
}

StepControl TimeControl::initial() const {
  StepControl c{};
  c.t[0] = s_.start_time;
  c.dt[0] = s_.delta_t;
  c.t_target = s_.end_time;
  c.dt_max = adaptive() ? s_.max_delta_t : s_.delta_t;
  c.cfl = adaptive() ? s_.max_co : 0;
  c.h = h_;
  // A fixed step only: an adaptive one follows the signal speed, and a spike of one step
  // (a point whose speed jumps: TwoPhase.TerzaghiConsolidation read Courant 20 once) is
  // corrected by the next step; its collapse is caught by the host (Solver::check_health).
  c.stop_co = adaptive() ? 0 : s_.stop_co;
  return c;
}

bool TimeControl::start(StepControl& ctl, Real cmax, std::ostream& log) {
  if (cmax <= 0) return false;
  const Real stable = h_ / cmax;
  if (adaptive()) {
    ctl.dt[0] = std::min<Real>(s_.delta_t, ctl.cfl * stable);
    ctl.last_speed = cmax;  // until a step measures one (advance_clock)
    return true;
  }
  if (s_.delta_t > stable) {
    log << "warning: system/controlDict: deltaT " << s_.delta_t << " s exceeds the stable time step " << stable
        << " s (h / c with the largest signal speed c = " << cmax
        << " m/s at the start); the run may blow up. Use a smaller deltaT or adjustTimeStep yes.\n";
    warned_ = true;
  }
  return false;
}

bool TimeControl::reached(double t, double target) {
  return t >= target - kReachedTolerance * std::max(1.0, std::fabs(target));
}

std::int64_t TimeControl::chunk_length(const StepControl& ctl, int p, double t_event, std::int64_t step_event,
                                       std::int64_t budget, std::int64_t report) const {
  std::int64_t n = steps_to(ctl, p, t_event);
  if (step_event > 0) n = std::min(n, step_event);
  if (budget > 0) n = std::min(n, budget);
  return std::min(n, std::max<std::int64_t>(report, 1));
}

std::int64_t TimeControl::steps_to(const StepControl& ctl, int p, double target) const {
  // A clock stopped on the last target (dt = 0, until retarget derives the step): one step,
  // after which the next chunk is sized from that step. (The step was clamped to 1e-300
  // and the quotient, ~1e298, converted to int64: undefined behaviour, found by UBSan, that
  // gave one step on x86.)
  const Real dt = ctl.dt[p];
  if (!(dt > 0)) return 1;
  const double steps = std::ceil((target - ctl.t[p]) / dt - kWholeStepsTolerance) + (adaptive() ? 1 : 0);
  return static_cast<std::int64_t>(std::clamp(steps, 1.0, kMaxSteps));
}

bool TimeControl::retarget(StepControl& ctl, int p, double target) const {
  if (ctl.t_target == target) return false;
  ctl.t_target = target;
  Real dt = ctl.dt_max;
  // A clock stopped on the old target (dt = 0) resumes at the CFL step of the last speed
  // measured: it measured none since (next_cfl_step; its speed has been cleared by then).
  if (adaptive()) dt = ctl.dt[p] > 0 ? std::min<Real>(dt, ctl.dt[p]) : next_cfl_step(ctl, 0);
  ctl.dt[p] = land_on_target(dt, target - ctl.t[p]);
  return true;
}

void TimeControl::watch(double wall, double t, std::int64_t step, const SignalSpeed& speed, std::ostream& log) {
  if (adaptive() || warned_ || wall - watch_wall_ < 5.0) return;
  watch_wall_ = wall;
  const Real cmax = speed();
  if (!(cmax > 0) || s_.delta_t <= h_ / cmax) return;
  log << "\nwarning: system/controlDict: at t = " << t << " s (step " << step << ") deltaT " << s_.delta_t
      << " s exceeds the stable time step " << h_ / cmax << " s (h / c, largest signal speed c = " << cmax
      << " m/s); the run may blow up. Use adjustTimeStep yes (maxCo 0.5) or a smaller deltaT.\n";
  warned_ = true;
}

}  // namespace scree
