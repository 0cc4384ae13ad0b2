// The algorithm choices of system/mpmSchemes, as the kernels see them.
#pragma once

#include <limits>

#include "scree/core/config.hpp"

namespace scree {

/// shapeFunction: linear (the tent functions of Feng et al. 2025, eq. 5), uGIMP or the
/// quadratic B-spline (shape_functions.hpp).
enum class ShapeKind : int { linear = 0, gimp = 1, bspline2 = 2 };

/// transfer: the particle velocity update, FLIP (blended with PIC) or APIC.
enum class Transfer : int { flip = 0, apic = 1 };

/// updateScheme: the order of the stress update in a step (solver/solver.hpp).
enum class UpdateScheme { USF, USL, MUSL };

/// maxVolumeRatio when the case gives none: no limit on det F (one comparison per point).
inline constexpr Real kNoVolumeLimit = std::numeric_limits<Real>::infinity();

}  // namespace scree
