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

}  // namespace scree
