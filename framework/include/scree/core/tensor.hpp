// Small fixed-size vectors and tensors usable on both backends.
//
// Vec<D>  : a D-vector.
// Mat<D>  : a D x D matrix, row-major, a(i,j).
// Sym3    : a symmetric 3x3 tensor in Voigt order (xx, yy, zz, xy, yz, zx), the order
//           ParaView expects for 6-component symmetric tensors (XX YY ZZ XY YZ XZ).
//
// Constitutive models always work on 3D tensors (Sym3): a plane-strain 2D problem has
// zero out-of-plane strain increments, and sigma_zz follows from the model. This keeps
// every material dimension-independent ("3D-ready").
//
// Sign convention: continuum mechanics, tension positive. Geomechanics quantities
// (p, q) computed here are compression-positive, as named.
#pragma once

#include <cmath>

#include "scree/core/config.hpp"

namespace scree {

template <int D>
struct Vec {
  Real v[D];
  SCREE_INLINE Real& operator[](int i) { return v[i]; }
  SCREE_INLINE const Real& operator[](int i) const { return v[i]; }
  SCREE_INLINE static Vec zero() {
    Vec r;
    for (int i = 0; i < D; ++i) r.v[i] = 0;
    return r;
  }
  SCREE_INLINE Vec& operator+=(const Vec& o) {
    for (int i = 0; i < D; ++i) v[i] += o.v[i];
    return *this;
  }
  SCREE_INLINE Vec& operator-=(const Vec& o) {
    for (int i = 0; i < D; ++i) v[i] -= o.v[i];
    return *this;
  }
  SCREE_INLINE Vec& operator*=(Real s) {
    for (int i = 0; i < D; ++i) v[i] *= s;
    return *this;
  }
};

template <int D>
SCREE_INLINE Vec<D> operator+(Vec<D> a, const Vec<D>& b) { return a += b; }
template <int D>
SCREE_INLINE Vec<D> operator-(Vec<D> a, const Vec<D>& b) { return a -= b; }
template <int D>
SCREE_INLINE Vec<D> operator*(Vec<D> a, Real s) { return a *= s; }
template <int D>
SCREE_INLINE Vec<D> operator*(Real s, Vec<D> a) { return a *= s; }
template <int D>
SCREE_INLINE Real dot(const Vec<D>& a, const Vec<D>& b) {
  Real s = 0;
  for (int i = 0; i < D; ++i) s += a.v[i] * b.v[i];
  return s;
}
template <int D>
SCREE_INLINE Real norm(const Vec<D>& a) { return sqrt(dot(a, a)); }
SCREE_INLINE Vec<3> cross(const Vec<3>& a, const Vec<3>& b) {
  return {{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}};
}

template <int D>
struct Mat {
  Real a[D][D];
  SCREE_INLINE Real& operator()(int i, int j) { return a[i][j]; }
  SCREE_INLINE const Real& operator()(int i, int j) const { return a[i][j]; }
  SCREE_INLINE static Mat zero() {
    Mat r;
    for (int i = 0; i < D; ++i)
      for (int j = 0; j < D; ++j) r.a[i][j] = 0;
    return r;
  }
  SCREE_INLINE static Mat identity() {
    Mat r = zero();
    for (int i = 0; i < D; ++i) r.a[i][i] = 1;
    return r;
  }
  SCREE_INLINE Mat& operator+=(const Mat& o) {
    for (int i = 0; i < D; ++i)
      for (int j = 0; j < D; ++j) a[i][j] += o.a[i][j];
    return *this;
  }
  SCREE_INLINE Mat& operator*=(Real s) {
    for (int i = 0; i < D; ++i)
      for (int j = 0; j < D; ++j) a[i][j] *= s;
    return *this;
  }
};

template <int D>
SCREE_INLINE Mat<D> operator+(Mat<D> a, const Mat<D>& b) { return a += b; }
template <int D>
SCREE_INLINE Mat<D> operator*(Mat<D> a, Real s) { return a *= s; }
template <int D>
SCREE_INLINE Mat<D> operator*(const Mat<D>& a, const Mat<D>& b) {
  Mat<D> r = Mat<D>::zero();
  for (int i = 0; i < D; ++i)
    for (int k = 0; k < D; ++k)
      for (int j = 0; j < D; ++j) r.a[i][j] += a.a[i][k] * b.a[k][j];
  return r;
}
template <int D>
SCREE_INLINE Vec<D> operator*(const Mat<D>& a, const Vec<D>& x) {
  Vec<D> r = Vec<D>::zero();
  for (int i = 0; i < D; ++i)
    for (int j = 0; j < D; ++j) r.v[i] += a.a[i][j] * x.v[j];
  return r;
}
/// Outer product a b^T.
template <int D>
SCREE_INLINE Mat<D> outer(const Vec<D>& a, const Vec<D>& b) {
  Mat<D> r;
  for (int i = 0; i < D; ++i)
    for (int j = 0; j < D; ++j) r.a[i][j] = a.v[i] * b.v[j];
  return r;
}
template <int D>
SCREE_INLINE Real trace(const Mat<D>& a) {
  Real s = 0;
  for (int i = 0; i < D; ++i) s += a.a[i][i];
  return s;
}
SCREE_INLINE Real det(const Mat<2>& a) { return a.a[0][0] * a.a[1][1] - a.a[0][1] * a.a[1][0]; }
SCREE_INLINE Real det(const Mat<3>& a) {
  return a.a[0][0] * (a.a[1][1] * a.a[2][2] - a.a[1][2] * a.a[2][1]) -
         a.a[0][1] * (a.a[1][0] * a.a[2][2] - a.a[1][2] * a.a[2][0]) +
         a.a[0][2] * (a.a[1][0] * a.a[2][1] - a.a[1][1] * a.a[2][0]);
}

/// Symmetric 3x3 tensor, Voigt order (xx, yy, zz, xy, yz, zx). Shear entries are
/// tensor components (not engineering strains).
struct Sym3 {
  Real s[6];
  SCREE_INLINE Real& operator[](int i) { return s[i]; }
  SCREE_INLINE const Real& operator[](int i) const { return s[i]; }
  SCREE_INLINE static Sym3 zero() { return Sym3{{0, 0, 0, 0, 0, 0}}; }
  SCREE_INLINE static Sym3 identity() { return Sym3{{1, 1, 1, 0, 0, 0}}; }
  SCREE_INLINE Real trace() const { return s[0] + s[1] + s[2]; }
  /// Component (i,j) of the full tensor.
  SCREE_INLINE Real operator()(int i, int j) const {
    if (i == j) return s[i];
    const int k = i + j;  // (0,1)->1 xy, (1,2)->3 yz, (0,2)->2 zx
    return k == 1 ? s[3] : (k == 3 ? s[4] : s[5]);
  }
  SCREE_INLINE Sym3& operator+=(const Sym3& o) {
    for (int i = 0; i < 6; ++i) s[i] += o.s[i];
    return *this;
  }
  SCREE_INLINE Sym3& operator-=(const Sym3& o) {
    for (int i = 0; i < 6; ++i) s[i] -= o.s[i];
    return *this;
  }
  SCREE_INLINE Sym3& operator*=(Real a) {
    for (int i = 0; i < 6; ++i) s[i] *= a;
    return *this;
  }
};

SCREE_INLINE Sym3 operator+(Sym3 a, const Sym3& b) { return a += b; }
SCREE_INLINE Sym3 operator-(Sym3 a, const Sym3& b) { return a -= b; }
SCREE_INLINE Sym3 operator*(Sym3 a, Real s) { return a *= s; }
SCREE_INLINE Sym3 operator*(Real s, Sym3 a) { return a *= s; }

/// Double contraction a:b of two symmetric tensors (shear terms counted twice).
SCREE_INLINE Real ddot(const Sym3& a, const Sym3& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + 2 * (a[3] * b[3] + a[4] * b[4] + a[5] * b[5]);
}
/// Deviatoric part a - tr(a)/3 I.
SCREE_INLINE Sym3 deviator(const Sym3& a) {
  const Real m = a.trace() / 3;
  return Sym3{{a[0] - m, a[1] - m, a[2] - m, a[3], a[4], a[5]}};
}
/// Norm sqrt(a:a).
SCREE_INLINE Real norm(const Sym3& a) { return sqrt(ddot(a, a)); }

/// Mean pressure, compression positive: p = -tr(sigma)/3 [Pa].
SCREE_INLINE Real pressure(const Sym3& sigma) { return -sigma.trace() / 3; }
/// Von Mises equivalent (deviatoric) stress q = sqrt(3/2 s:s) [Pa].
SCREE_INLINE Real deviatoric_stress(const Sym3& sigma) {
  const Sym3 d = deviator(sigma);
  return sqrt(Real(1.5) * ddot(d, d));
}
/// Equivalent deviatoric strain (increment) sqrt(2/3 e:e), work-conjugate to q.
SCREE_INLINE Real equivalent_deviatoric_strain(const Sym3& eps) {
  const Sym3 d = deviator(eps);
  return sqrt(Real(2) / 3 * ddot(d, d));
}

/// Symmetric part of a DxD matrix embedded in 3D (plane strain: zz, yz, zx = 0).
SCREE_INLINE Sym3 sym3_from(const Mat<2>& l) {
  return Sym3{{l.a[0][0], l.a[1][1], 0, Real(0.5) * (l.a[0][1] + l.a[1][0]), 0, 0}};
}
SCREE_INLINE Sym3 sym3_from(const Mat<3>& l) {
  return Sym3{{l.a[0][0], l.a[1][1], l.a[2][2], Real(0.5) * (l.a[0][1] + l.a[1][0]),
               Real(0.5) * (l.a[1][2] + l.a[2][1]), Real(0.5) * (l.a[2][0] + l.a[0][2])}};
}

/// Spin (skew part) W = (L - L^T)/2 of a velocity gradient, as the three independent
/// components (w_xy, w_yz, w_zx) with W = [[0, w_xy, -w_zx], [-w_xy, 0, w_yz], [w_zx, -w_yz, 0]].
struct Spin3 {
  Real xy, yz, zx;
  SCREE_INLINE static Spin3 zero() { return Spin3{0, 0, 0}; }
};
SCREE_INLINE Spin3 spin_from(const Mat<2>& l) {
  return Spin3{Real(0.5) * (l.a[0][1] - l.a[1][0]), 0, 0};
}
SCREE_INLINE Spin3 spin_from(const Mat<3>& l) {
  return Spin3{Real(0.5) * (l.a[0][1] - l.a[1][0]), Real(0.5) * (l.a[1][2] - l.a[2][1]),
               Real(0.5) * (l.a[2][0] - l.a[0][2])};
}

/// Objective (co-rotational) update of a symmetric tensor over an increment, for the
/// spin increment w = W dt (W = skew part of the velocity gradient):
///   a <- Q a Q^T,  Q = (I - w/2)^{-1} (I + w/2)      (Hughes & Winget 1980)
/// Q is exactly orthogonal for any increment, and to first order this is the Jaumann
/// rate a <- a + (w a - a w). It replaces the small-strain measure 1/2(F + F^T) - I of
/// Feng et al. 2025, eq. 9, which is not objective under the large rotations of a flow.
SCREE_INLINE Sym3 corotate(const Sym3& a, const Spin3& w) {
  // Spin matrix W (skew): W = [[0, xy, -zx], [-xy, 0, yz], [zx, -yz, 0]].
  const Real hx = Real(0.5) * w.yz, hy = Real(0.5) * w.zx, hz = Real(0.5) * w.xy;
  // For a skew matrix with axial vector h (W/2 x = h x x with this layout),
  // Q = I + 2/(1+|h|^2) (H + H^2), H the skew matrix of h (Cayley transform).
  const Real H[3][3] = {{0, hz, -hy}, {-hz, 0, hx}, {hy, -hx, 0}};
  Real H2[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      Real s = 0;
      for (int k = 0; k < 3; ++k) s += H[i][k] * H[k][j];
      H2[i][j] = s;
    }
  const Real c = 2 / (1 + hx * hx + hy * hy + hz * hz);
  Real Q[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) Q[i][j] = (i == j ? 1 : 0) + c * (H[i][j] + H2[i][j]);
  Real QA[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      Real s = 0;
      for (int k = 0; k < 3; ++k) s += Q[i][k] * a(k, j);
      QA[i][j] = s;
    }
  Real R[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = i; j < 3; ++j) {
      Real s = 0;
      for (int k = 0; k < 3; ++k) s += QA[i][k] * Q[j][k];
      R[i][j] = s;
    }
  return Sym3{{R[0][0], R[1][1], R[2][2], R[0][1], R[1][2], R[0][2]}};
}

}  // namespace scree
