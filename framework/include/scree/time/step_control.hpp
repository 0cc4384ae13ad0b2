// Time control on the device: the state of the clock and the per-step advance.
//
// The clock lives in device memory (StepControl) so that no step needs a host round trip.
// Two slots alternate with the step's parity: kernels of step k read slot k%2, and the
// last kernel of the step (the grid update's thread 0) writes slot (k+1)%2 after the rest
// of the step has used slot k%2. The step lands exactly on t_target (a write time or the
// end); after that dt is 0 and steps change nothing until the host sets the next target.
// The host side (the stable step, the first step, a new target, the watch over a fixed
// step) is TimeControl (time_control.hpp); the step-size rules shared by both are here.
#pragma once

#include <cmath>

#include "scree/core/config.hpp"

namespace scree {

struct StepControl {
  Real t[2];          ///< time at the start of the step [s]
  Real dt[2];         ///< the step's time increment [s]
  Real max_speed[2];  ///< largest particle signal speed c + |v| seen in the step [m/s]
  Real t_target;      ///< the time to land on (next write or end) [s]
  Real dt_max;        ///< fixed step, or the largest adaptive step [s]
  Real cfl;           ///< CFL number (0: fixed step)
  Real h;             ///< cell size [m]
  unsigned long long steps_done;  ///< steps that did work
  unsigned long long lost;        ///< particles whose stencil left the grid (frozen)
  unsigned long long step[2];     ///< index of the step (every step, also those with dt = 0)
};

/// The step that lands on a target `remaining` seconds ahead: the remainder when dt would
/// overshoot it or stop short of it by less than 1e-6 dt (no sliver of a step), else dt.
SCREE_INLINE Real land_on_target(Real dt, Real remaining) {
  return remaining < dt * (1 + Real(1e-6)) ? remaining : dt;
}

/// The adaptive step from the largest signal speed c + |v| seen in a step:
/// dt = CFL h / (c + |v|)_max, at most dt_max (Courant, Friedrichs & Lewy 1928).
SCREE_INLINE Real cfl_step(const StepControl& c, Real max_speed) {
  Real dt = c.dt_max;
  if (c.cfl > 0 && max_speed > 0) dt = fmin(dt, c.cfl * c.h / max_speed);
  return dt;
}

/// Advance the clock past step `par` and choose the next step (slot 1 - par). One thread
/// runs this, at the end of the step; it writes slots nobody else reads in this step.
SCREE_INLINE void advance_clock(StepControl* c, int par) {
  const Real t = c->t[par], dt = c->dt[par];
  const Real t1 = t + dt;
  Real dt1 = cfl_step(*c, c->max_speed[par]);
  const Real remaining = c->t_target - t1;
  // On the target (within round-off): stop until the host sets the next one.
  dt1 = remaining <= Real(1e-9) * dt1 ? Real(0) : land_on_target(dt1, remaining);
  c->t[1 - par] = t1;
  c->dt[1 - par] = dt1;
  c->max_speed[par] = 0;
  c->step[1 - par] = c->step[par] + 1;
  if (dt > 0) c->steps_done += 1;
}

}  // namespace scree
