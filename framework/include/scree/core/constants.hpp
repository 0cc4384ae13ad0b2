// Named constants shared by the framework, the plugins and the kernels, each written once:
// pi, the "no bound" of an open interval, and the tolerances that decide when two times
// are the same time.
#pragma once

#include <numbers>

#include "scree/core/config.hpp"

namespace scree {

/// pi, for host and device code alike (a constexpr scalar, usable in kernels).
inline constexpr Real kPi = std::numbers::pi_v<Real>;

/// "No bound": the default end of an open interval (startTime -kUnbounded, endTime
/// kUnbounded) and the seed of a minimum or maximum search. Finite on purpose: it survives
/// the arithmetic done with it (t - t_start, comparisons under fast-math) and prints as a
/// number in --list-plugins.
inline constexpr Real kUnbounded = 1e300;

// When two times are the same time. A clock that adds steps of dt to t arrives at a
// target with a round-off error; each test below allows for it where it asks, with the
// scale of the quantity it compares. Changing one changes which step lands where.

/// TimeControl::reached: a time t has reached `target` when t >= target - this *
/// max(1, |target|) (relative to the time: the round-off of a sum of many steps).
inline constexpr double kReachedTolerance = 1e-12;

/// TimeControl::steps_to: the steps to a target, ceil(remaining / dt - this): a remainder
/// that is a whole number of steps within round-off takes that number, not one more.
inline constexpr double kWholeStepsTolerance = 1e-9;

/// land_on_target (time/step_control.hpp): a step that would stop short of the target by
/// less than this fraction of dt is stretched onto it (no sliver of a step after it).
inline constexpr Real kLandingSlack = 1e-6;

/// advance_clock (time/step_control.hpp): the clock is on its target when what remains is
/// at most this fraction of the next step; it stops there until the next target is set.
inline constexpr Real kOnTargetTolerance = 1e-9;

// The grid (case/case_model.hpp): the domain of system/gridDict in whole cells.

/// A domain extent that is this many cells over a whole number of cells (round-off of
/// (upper - lower) / h) is that whole number; no cell is added for it.
inline constexpr Real kWholeCellTolerance = 1e-9;

/// An extent further than this from a whole number of cells is extended to the next whole
/// cell with a warning (the user's box is not a whole number of cells).
inline constexpr Real kWholeCellWarning = 1e-6;

}  // namespace scree
