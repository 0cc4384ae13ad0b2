// The algorithm choices of system/mpmSchemes, as the kernels see them.
#pragma once

#include <cmath>
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

/// damping: whether the local damping acts at time t (coefficient c > 0, t in [start, end)).
SCREE_INLINE bool damping_active(Real c, Real t, Real start, Real end) { return c > 0 && t >= start && t < end; }
/// damping: a nodal force component with the local damping, f - c |f| sign(v) (Cundall's
/// local damping, opposing the node's velocity v); f where v = 0.
SCREE_INLINE Real damped_force(Real f, Real v, Real c) {
  return v != 0 ? f - c * fabs(f) * (v > 0 ? Real(1) : Real(-1)) : f;
}

}  // namespace scree
