// Shape functions of the background grid (1D factors; D-dimensional = tensor product).
//
//   ShapeLinear   : the paper's bilinear/trilinear tent functions (2 nodes per axis).
//                   Cell-crossing noise: gradients jump when a particle crosses a cell.
//   ShapeGimp     : uGIMP (Bardenhagen & Kober 2004) with the undeformed particle
//                   half-length lp = h / (2 n), n particles per cell per axis (3 nodes).
//   ShapeBspline2 : quadratic B-spline (Steffen et al. 2008), C1 (3 nodes).
//
// eval(xi, base, w, dw): for a particle at grid coordinate xi = (x - origin)/h, returns
// the first stencil node `base` and the weights w[a] and derivatives dw[a] (per metre)
// of nodes base + a, a = 0..kStencil-1. All weights sum to 1 (partition of unity) and
// reproduce linear fields (sum_a w[a] (base + a) = xi), which the tests check.
#pragma once

#include <cmath>

#include "scree/core/config.hpp"
#include "scree/mpm/schemes.hpp"

namespace scree {

struct ShapeLinear {
  static constexpr int kStencil = 2;
  Real inv_h;
  SCREE_INLINE void eval(Real xi, int& base, Real* w, Real* dw) const {
    const Real f = floor(xi);
    base = static_cast<int>(f);
    const Real r = xi - f;  // in [0, 1)
    w[0] = 1 - r;
    w[1] = r;
    dw[0] = -inv_h;
    dw[1] = inv_h;
  }
};

struct ShapeBspline2 {
  static constexpr int kStencil = 3;
  Real inv_h;
  SCREE_INLINE void eval(Real xi, int& base, Real* w, Real* dw) const {
    const Real f = floor(xi - Real(0.5));
    base = static_cast<int>(f);
    const Real r = xi - f;  // in [0.5, 1.5): distance from node `base` in cells
    const Real a = Real(1.5) - r, b = r - 1, c = r - Real(0.5);
    w[0] = Real(0.5) * a * a;
    w[1] = Real(0.75) - b * b;
    w[2] = Real(0.5) * c * c;
    dw[0] = -a * inv_h;
    dw[1] = -2 * b * inv_h;
    dw[2] = c * inv_h;
  }
};

struct ShapeGimp {
  static constexpr int kStencil = 3;
  Real inv_h;
  Real lp;  ///< particle half-length in cell units, 0 < lp <= 0.5
  /// 1D uGIMP weight and derivative (per cell) at signed distance d (in cells).
  SCREE_INLINE void weight(Real d, Real& w, Real& dw) const {
    const Real ad = fabs(d), s = d < 0 ? Real(-1) : Real(1);
    if (ad < lp) {
      w = 1 - (d * d + lp * lp) / (2 * lp);
      dw = -d / lp;
    } else if (ad < 1 - lp) {
      w = 1 - ad;
      dw = -s;
    } else if (ad < 1 + lp) {
      const Real t = 1 + lp - ad;
      w = t * t / (4 * lp);
      dw = -s * t / (2 * lp);
    } else {
      w = 0;
      dw = 0;
    }
  }
  SCREE_INLINE void eval(Real xi, int& base, Real* w, Real* dw) const {
    base = static_cast<int>(floor(xi + Real(0.5))) - 1;  // nearest node - 1
    for (int a = 0; a < 3; ++a) {
      Real wa, da;
      weight(xi - (base + a), wa, da);  // d = x_p - x_I
      w[a] = wa;
      dw[a] = da * inv_h;  // dN_I/dx at x_p: the weight is a function of x_p - x_I
    }
  }
};

}  // namespace scree
