// Time control on the device: the state of the clock and the per-step advance.
//
// The clock lives in device memory (StepControl) so that no step needs a host round trip.
// Two slots alternate with the step's parity: kernels of step k read slot k%2, and the
// last kernel of the step (the grid update's thread 0) writes slot (k+1)%2 after the rest
// of the step has used slot k%2. The step lands exactly on t_target (a write time or the
// end); after that dt is 0 and steps change nothing until the host sets the next target.
// The host side (the stable step, the first step, a new target, the watch over a fixed
// step) is TimeControl (time_control.hpp); the step-size rules shared by both are here.
//
// Health: the grid update counts nodes whose velocity or force is not finite (every
// non-finite velocity, stress or mass of a point reaches them in the step's P2G; the host
// then finds the point: report_nonfinite_node; a non-finite position comes from a
// non-finite nodal velocity of the same step), and the kernels' lost-point count and the
// step's signal speed are here already. advance_clock turns them into `failure`
// and then stops the clock (dt = 0): a run gone wrong freezes on the device in the step
// it went wrong, at no cost to a healthy step (no host round trip), and the host finds
// `failure` when it reads the clock between chunks of steps (Solver::check_health).
#pragma once

#include <cmath>

#include "scree/core/config.hpp"
#include "scree/core/constants.hpp"
#include "scree/output/energy_ledger.hpp"

namespace scree {

/// Why the clock stopped (StepControl::failure, bits).
enum StepFailure : unsigned {
  kFailNonFinite = 1u << 0,  ///< a point's position, velocity or stress is not finite
  kFailLost = 1u << 1,       ///< more points left the grid than lost_stop allows
  kFailUnstable = 1u << 2,   ///< a step's Courant number dt (c + |v|)_max / h exceeded stop_co
  kFailStalled = 1u << 3,    ///< (set by the host) the adaptive step became too small to reach the end
  kFailElsewhere = 1u << 4,  ///< (set by the host) another rank of a decomposed run stopped its clock
  kFailHalo = 1u << 5,       ///< (set by the host) a point moved past its rank's halo between two migrations
};

/// The field of the first non-finite value (StepControl::BadPoint::field).
enum BadField : int { kBadPosition = 0, kBadVelocity = 1, kBadStress = 2 };

struct StepControl {
  Real t[2];          ///< time at the start of the step [s]
  Real dt[2];         ///< the step's time increment [s]
  Real max_speed[2];  ///< largest particle signal speed c + |v| seen in the step [m/s]
  /// The largest signal speed of the last step that saw one [m/s] (max_speed is cleared
  /// after each step): the step after the clock stopped on a target is derived from it.
  Real last_speed;
  Real t_target;      ///< the time to land on (next write or end) [s]
  Real dt_max;        ///< fixed step, or the largest adaptive step [s]
  Real cfl;           ///< CFL number (0: fixed step)
  Real h;             ///< cell size [m]
  unsigned long long steps_done;  ///< steps that did work
  unsigned long long lost;        ///< particles whose stencil left the grid (frozen)
  unsigned long long step[2];     ///< index of the step (every step, also those with dt = 0)
  // Health (see the top of this file); zero-initialised is "healthy, nothing checked".
  unsigned long long lost_stop;   ///< the run stops once this many points have left the grid (0: never)
  Real stop_co;                   ///< the run stops after a step of Courant number above this (0: never)
  /// Non-finite nodal values found by the grid update; the first (count 0 -> 1) records its
  /// step, and the host fills in the point (Solver::diagnosis; index -1 until then).
  struct BadPoint {
    unsigned long long count;
    int body;          ///< Body::body_id
    int field;         ///< BadField
    int component;     ///< the component of the field
    Index index;       ///< the point's index in its body's storage at the time
    Real value;        ///< the non-finite value
    unsigned long long step;  ///< the step in which it was found
  } bad;
  BadPoint first_lost;            ///< the first point that left the grid (count, field, value unused)
  unsigned failure;               ///< StepFailure bits (0: healthy)
  unsigned long long failed_step; ///< the step after which the clock stopped
  Real failed_co;                 ///< that step's Courant number dt (c + |v|)_max / h
  /// The energy ledger (output/energy_ledger.hpp), cumulative since t = 0: lives with the
  /// clock, so that a checkpoint carries it and a restart continues it. Kept only when
  /// PassPolicy::energy / GridUpdateParams::energy is set: off, nothing is added.
  EnergySlots energy;
};

/// Health: a node of the grid update found a non-finite velocity or force (every
/// non-finite stress, velocity or mass of a point reaches its stencil's nodes in the step's
/// P2G). Counted; the clock stops after the step (advance_clock), and the host finds the
/// point in the frozen state (Solver::diagnosis). The particle pass itself tests nothing:
/// inline tests there are paid per point and per step, a measurable share of the step;
/// the grid update is a small share of a step.
SCREE_INLINE void report_nonfinite_node(StepControl* c, int par) {
#if defined(__CUDA_ARCH__)
  if (atomicAdd(&c->bad.count, 1ull) != 0) return;
#else
  if (__atomic_fetch_add(&c->bad.count, 1ull, __ATOMIC_RELAXED) != 0) return;
#endif
  c->bad.index = -1;  // the point: found by the host
  c->bad.step = c->step[par];
  // Stop the clock after this step, whether or not advance_clock (node 0 of this very
  // kernel) has run yet: the state the host inspects is the one that went wrong.
  c->failure |= kFailNonFinite;
  c->failed_step = c->step[par];
  c->dt[1 - par] = 0;
}

/// The step that lands on a target `remaining` seconds ahead: the remainder when dt would
/// overshoot it or stop short of it by less than kLandingSlack dt (no sliver of a step),
/// else dt.
SCREE_INLINE Real land_on_target(Real dt, Real remaining) {
  return remaining < dt * (1 + kLandingSlack) ? remaining : dt;
}

/// The adaptive step from the largest signal speed c + |v| seen in a step:
/// dt = CFL h / (c + |v|)_max, at most dt_max (Courant, Friedrichs & Lewy 1928).
SCREE_INLINE Real cfl_step(const StepControl& c, Real max_speed) {
  Real dt = c.dt_max;
  if (c.cfl > 0 && max_speed > 0) dt = fmin(dt, c.cfl * c.h / max_speed);
  return dt;
}

/// The step after one that measured the signal speed `measured` (0: it measured none):
/// the CFL step of that speed, or of the last speed measured (StepControl::last_speed)
/// when there is none. A step may measure none: USL's step after the start or after a
/// flush (a write) has no stress update of its own (it ran in the flush, or runs in the
/// next step's pass), and a clock stopped on a target resumes after its speed was cleared.
/// A cleared speed taken as measured would give maxDeltaT, far above the CFL step
/// (tests/verification/restart checks the step after a start). The host keeps last_speed with the
/// device's (Solver::flush reads the clock back after the gather that measures it).
SCREE_INLINE Real next_cfl_step(const StepControl& c, Real measured) {
  return cfl_step(c, measured > 0 ? measured : c.last_speed);
}

/// Advance the clock past step `par` and choose the next step (slot 1 - par). One thread
/// runs this, at the end of the step; it writes slots nobody else reads in this step.
SCREE_INLINE void advance_clock(StepControl* c, int par) {
  const Real t = c->t[par], dt = c->dt[par];
  const Real t1 = t + dt;
  Real dt1 = next_cfl_step(*c, c->max_speed[par]);
  const Real remaining = c->t_target - t1;
  // On the target (within round-off): stop until the host sets the next one.
  dt1 = remaining <= kOnTargetTolerance * dt1 ? Real(0) : land_on_target(dt1, remaining);
  // Health: a failure stops the clock for good (the host ends the run when it sees it).
  unsigned fail = 0;
  if (c->bad.count > 0) fail |= kFailNonFinite;
  if (c->lost_stop > 0 && c->lost >= c->lost_stop) fail |= kFailLost;
  const Real co = dt * c->max_speed[par] / c->h;
  if (c->stop_co > 0 && dt > 0 && !(co <= c->stop_co)) fail |= kFailUnstable;
  if (fail != 0 && c->failure == 0) {
    c->failure = fail;
    c->failed_step = c->step[par];
    c->failed_co = co;
  }
  if (c->failure != 0) dt1 = 0;
  c->t[1 - par] = t1;
  c->dt[1 - par] = dt1;
  // Only a step that advanced the clock: an idle step's speed (dt = 0, on a target; the
  // pore liquid's scatter still measures one, the solid's stress update does not run) is a
  // different quantity, and how many idle steps a run takes depends on where its chunks of
  // steps ended (the wall clock): the step after a write depended on it, and a two-phase run
  // did not reproduce itself (cases/rainfallSlope, two runs of one binary on one thread).
  if (dt > 0 && c->max_speed[par] > 0) c->last_speed = c->max_speed[par];
  c->max_speed[par] = 0;
  c->step[1 - par] = c->step[par] + 1;
  if (dt > 0) c->steps_done += 1;
}

}  // namespace scree
