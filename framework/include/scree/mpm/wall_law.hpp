// Grid-node constraints: what boundary conditions do to nodal velocities.
//
// Most boundary conditions act on grid nodes only: fixed (no-slip), slip (roller) and
// frictional walls on a plane, active over a time window. They are recorded as
// Constraint entries (at most kMaxConstraints per case) and a bit mask per node saying
// which entries apply; the grid-update kernel applies them to v^k and v^{k+1} right
// after it computes them, on the device, with no extra launch and no host round trip
// (so a gate opens at its time even inside a CUDA graph). Boundary conditions that need
// their own kernels (e.g. two-phase rainfall) use BoundaryCondition's hooks instead.
#pragma once

#include <cstdint>

#include "scree/core/config.hpp"
#include "scree/core/tensor.hpp"

namespace scree {

inline constexpr int kMaxConstraints = 32;
using ConstraintMask = std::uint32_t;

enum class ConstraintType : int {
  fixed = 0,     ///< v = prescribed value (zero: no-slip)
  slip = 1,      ///< v.n = 0 (roller), or only v.n >= 0 when `separable` (contact)
  friction = 2,  ///< Coulomb friction on a wall with normal n (pointing into the material)
  rotation = 3,  ///< v = omega x (x_node - centre): a rigidly rotating wall or drive
};

struct Constraint {
  ConstraintType type = ConstraintType::fixed;
  Real normal[3] = {0, 0, 0};  ///< unit normal pointing into the material (slip, friction)
  Real value[3] = {0, 0, 0};   ///< prescribed velocity (fixed) [m/s]
  Real mu = 0;                 ///< friction coefficient (friction)
  Real omega[3] = {0, 0, 0};   ///< angular velocity (rotation; 2D uses omega[2]) [rad/s]
  Real centre[3] = {0, 0, 0};  ///< centre of rotation (rotation) [m]
  Real t_start = -1e300;       ///< active for t_start <= t < t_end [s]
  Real t_end = 1e300;
  int separable = 0;           ///< slip/friction: the material may leave the wall

  /// Apply to the velocity v (D components) of the node at position x, at time t.
  template <int D>
  SCREE_INLINE void apply(Real* v, const Real* x, Real t) const {
    if (t < t_start || t >= t_end) return;
    if (type == ConstraintType::fixed) {
      for (int d = 0; d < D; ++d) v[d] = value[d];
      return;
    }
    if (type == ConstraintType::rotation) {
      Real r[3] = {0, 0, 0};
      for (int d = 0; d < D; ++d) r[d] = x[d] - centre[d];
      const Real w[3] = {omega[0], omega[1], omega[2]};
      const Real c[3] = {w[1] * r[2] - w[2] * r[1], w[2] * r[0] - w[0] * r[2], w[0] * r[1] - w[1] * r[0]};
      for (int d = 0; d < D; ++d) v[d] = c[d];
      return;
    }
    Real vn = 0;
    for (int d = 0; d < D; ++d) vn += v[d] * normal[d];
    if (separable && vn >= 0) return;  // moving away from the wall: free
    if (type == ConstraintType::slip) {
      for (int d = 0; d < D; ++d) v[d] -= vn * normal[d];
      return;
    }
    // Coulomb friction (Bardenhagen et al. 2001 for a rigid wall): remove the normal
    // approach velocity and reduce the tangential velocity by mu |v_n|, not past zero.
    Real vt[3], vt2 = 0;
    for (int d = 0; d < D; ++d) {
      vt[d] = v[d] - vn * normal[d];
      vt2 += vt[d] * vt[d];
    }
    const Real vtn = sqrt(vt2);
    const Real scale = vtn > 0 ? fmax(Real(0), vtn - mu * fabs(vn)) / vtn : Real(0);
    for (int d = 0; d < D; ++d) v[d] = vt[d] * scale;
  }
};

/// Apply every constraint whose bit is set in `mask`, in index order.
template <int D>
SCREE_INLINE void apply_constraints(const Constraint* table, ConstraintMask mask, Real* v, const Real* x, Real t) {
  while (mask) {
#if defined(__CUDA_ARCH__)
    const int b = __ffs(static_cast<int>(mask)) - 1;
#else
    const int b = __builtin_ctz(mask);
#endif
    table[b].template apply<D>(v, x, t);
    mask &= mask - 1;
  }
}

}  // namespace scree
