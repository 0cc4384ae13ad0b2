// SIMSAND-type critical-state frictional model: the pieces of its stress integration.
//
// What integrate() (simsand_integrator.hpp) is made of, each a step of Sloan, Abbo & Sheng's
// (2001) explicit substepping or of the additions materials/simsand/README.md describes:
// the drift correction onto the yield surface, the elastic path and the Pegasus search of
// its yield crossing, the stress-free apex and separation, one modified-Euler (Heun) substep
// and its local error, and the implicit returns of stiff remainders. The formulas they
// evaluate: simsand_formulas.hpp. Units and signs as there: stresses in Pa, tension
// positive; p and q compression positive; strain increments tension positive.
//
// Device code: only <cmath> functions; no exceptions, allocation, recursion or lambdas.
#pragma once

#include <cmath>

#include "scree/core/config.hpp"
#include "scree/core/constants.hpp"
#include "scree/core/tensor.hpp"
#include "scree/materials/simsand_formulas.hpp"
#include "scree/materials/simsand_params.hpp"

namespace scree::materials::simsand {

inline constexpr Real kFtol = 1e-9;        ///< yield-function tolerance (f is a stress ratio)
inline constexpr Real kMinSubstep = 1e-4;  ///< smallest substep, as a fraction of the increment
inline constexpr int kApexIter = 8;        ///< rate evaluations to locate where a substep reaches the apex
/// Stiff updates (integrate(), README step 5): after kStiffAfter substep attempts, a remainder
/// that would need more than kStiffRemaining substeps of the current size is done in
/// kReturnSubsteps implicit returns, if the state is looser than critical and p does not grow
/// along them.
inline constexpr int kStiffAfter = 64;
inline constexpr Real kStiffRemaining = 32;
inline constexpr int kReturnSubsteps = 8;

/// Put a stress on the yield surface by scaling its deviator at constant p and Lode angle
/// (drift correction; also used for initial stresses outside the surface).
template <class Pol = Production>
SCREE_HD inline void project_to_surface(const Params& P, Sym3& sig, Real e, Real kappa) {
  const Invariants v = invariants(sig);
  if (!(v.p > P.papex) || !(v.q > 0)) return;
  const Real qt = hardening(P, peak_ratio<Pol>(P, e, v.p), kappa) * lode_g<Pol>(P, v.S) * v.p;
  sig = from_p_s(v.p, v.s * (qt / v.q));
}

/// f = yield() followed, when f > kFtol (or |f| > kFtol with `both_sides`), by
/// project_to_surface(), with the invariants, M_p and g(theta) evaluated once for both: the
/// same numbers as the two calls. Returns f before the projection; `projected` says whether
/// sig changed. `at`, if not null, receives g(theta) and M_p's parts for a plastic rate at
/// (sig, e) (valid only where p > p_apex).
template <class Pol = Production>
SCREE_HD inline Real yield_and_project(const Params& P, Sym3& sig, Real e, Real kappa, bool both_sides,
                                       bool& projected, PointRatios* at = nullptr) {
  projected = false;
  if (at) at->valid = false;
  const Invariants v = invariants(sig);
  if (!(v.p > P.papex)) return 0;
  const Real g = lode_g<Pol>(P, v.S);
  const PeakRatio k = peak<Pol>(P, e, v.p);
  if (at) *at = PointRatios{g, k, true};
  const Real f = yield_value(P, v.q, v.p, g, k.Mp, kappa);
  if ((both_sides ? fabs(f) : f) > kFtol && v.q > 0) {
    sig = from_p_s(v.p, v.s * (hardening(P, k.Mp, kappa) * g * v.p / v.q));
    projected = true;
  }
  return f;
}

/// Material point separated (tension): stress-free; the deviatoric strain of the remaining
/// fraction counts as plastic (free flow at zero stress).
SCREE_HD inline void separate(Sym3& sig, Vars& v, const Sym3& deps, Real frac) {
  sig = Sym3::zero();
  const Real ed = equivalent_deviatoric_strain(deps) * frac;
  v.kappa += ed;
  v.epsEq += ed;
}

/// f along the elastic path at fraction a of deps from sig0.
template <class Pol = Production>
SCREE_HD inline Real elastic_path_yield(const Params& P, const Sym3& sig0, Real kappa, Real ope0, const Sym3& deps,
                                        Real a, Sym3& sig_a) {
  const Real tr = deps.trace();
  if (!elastic_predictor<Pol>(P, sig0, void_ratio_at(ope0, tr, Real(0.5) * a), deps * a, sig_a)) return 1;
  return yield<Pol>(P, sig_a, void_ratio_at(ope0, tr, a), kappa);
}

/// The Pegasus method (Dowell & Jarratt 1972), a secant search that keeps a root bracketed,
/// used by every scalar search below: the next point from the bracket (xa, fa), (xb, fb), with
/// (xb, fb) the latest evaluation, ...
SCREE_HD inline Real pegasus_point(Real xa, Real fa, Real xb, Real fb) { return xb - fb * (xb - xa) / (fb - fa); }
/// ... and the bracket after f(x) = fx: x replaces xb; where the sign did not change, fa is
/// scaled by fb/(fb + fx) (Pegasus' rule; plain regula falsi would keep fa and stall).
SCREE_HD inline void pegasus_bracket(Real x, Real fx, Real& xa, Real& fa, Real& xb, Real& fb) {
  if (fx * fb < 0) {
    xa = xb;
    fa = fb;
  } else {
    fa = fa * fb / (fb + fx);
  }
  xb = x;
  fb = fx;
}

/// Pegasus search of the elastic fraction a in (a0, a1) where the elastic path crosses f = 0
/// (f0 < 0 < f1).
template <class Pol = Production>
SCREE_HD inline Real yield_crossing(const Params& P, const Sym3& sig0, Real kappa, Real ope0, const Sym3& deps,
                                    Real a0, Real f0, Real a1, Real f1) {
  Sym3 tmp;
  for (int it = 0; it < 60; ++it) {
    const Real a = pegasus_point(a0, f0, a1, f1);
    const Real fa = elastic_path_yield<Pol>(P, sig0, kappa, ope0, deps, a, tmp);
    if (fabs(fa) <= kFtol) return a;
    pegasus_bracket(a, fa, a0, f0, a1, f1);
    if (fabs(a1 - a0) < Real(1e-14)) break;
  }
  return fmin(a0, a1) > 0 ? fmin(a0, a1) : Real(0);
}

/// Apex branch: the increment deps from the stress-free apex (sigma = 0), e_mid the void ratio
/// of the elastic predictor (mid-increment), e1 at the end. An extension separates (sigma = 0,
/// the deviatoric strain is plastic); a compression rebuilds stress by the elastic trial from
/// zero, returned radially in the deviatoric plane (constant p) onto the cone. Isochoric shear
/// keeps the point stress-free. Does not update v.e.
template <class Pol = Production>
SCREE_HD inline void apex_update(const Params& P, Sym3& sig, Vars& v, const Sym3& deps, Real e_mid, Real e1) {
  Sym3 st;
  if (!elastic_predictor<Pol>(P, Sym3::zero(), e_mid, deps, st)) {
    separate(sig, v, deps, 1);
    return;
  }
  const Invariants iv = invariants(st);
  const Real H = hardening(P, peak_ratio<Pol>(P, e1, iv.p), v.kappa);
  const Real qt = H * lode_g<Pol>(P, iv.S) * iv.p;
  if (iv.q > qt && iv.q > 0) {  // return radially in the deviatoric plane at constant p
    const Real dq = iv.q - qt;
    const Real G = P.rG * bulk_modulus<Pol>(P, e1, iv.p);
    st = from_p_s(iv.p, iv.s * (qt / iv.q));
    v.kappa += dq / (3 * G);
    v.epsEq += dq / (3 * G);
  }
  sig = st;
}

/// One modified-Euler (Heun) substep of size x (fraction of the plastic part drem) from
/// (sig, kappa) at void ratio ea: the first rate is r1u (for the whole of drem) scaled by x,
/// the second is evaluated at the Euler end state. Returns false when the second rate cannot be
/// evaluated (the Euler end state has p <= p_apex); sn, kn are then the Euler end state.
template <class Pol = Production>
SCREE_HD inline bool heun_substep(const Params& P, const Sym3& sig, Real kappa, const Rate& r1u, const Sym3& drem,
                                  Real x, Real eb, Real de, Rate& r1, Rate& r2, Sym3& sn, Real& kn) {
  r1.dsig = r1u.dsig * x;
  r1.dkappa = r1u.dkappa * x;
  r1.deq = r1u.deq * x;
  r1.num = r1u.num * x;
  sn = sig + r1.dsig;
  kn = kappa + r1.dkappa;
  if (!plastic_rate<Pol>(P, sn, kn, eb, drem * x, de, r2)) return false;
  sn = sig + (r1.dsig + r2.dsig) * Real(0.5);
  kn = kappa + Real(0.5) * (r1.dkappa + r2.dkappa);
  return true;
}

/// Sloan et al. (2001)'s factor for the next substep size after one with local error R,
/// 0.9 sqrt(STOL/R); the callers bound it: at least 0.1 after a rejection, at most 1.1 after
/// an acceptance.
SCREE_HD inline Real substep_factor(const Params& P, Real R) { return Real(0.9) * sqrt(P.stol / R); }

/// Local error estimate of a Heun substep (Sloan et al. 2001): relative to max(|sigma|, s_e).
SCREE_HD inline Real heun_error(const Params& P, const Rate& r1, const Rate& r2, const Sym3& sn, Real kn) {
  // Relative error with a floor of 1e-3 p_at (~100 Pa): near a free surface the
  // stress is a few Pa and each MPM increment changes it by as much again, so a
  // purely relative error asked for hundreds of substeps per update there while
  // the absolute error (stol x 100 Pa = 0.01 Pa at 1e-4) is far below anything
  // the flow can feel.
  const Real es = norm(r2.dsig - r1.dsig) / fmax(norm(sn), P.serr);
  const Real ek = fabs(r2.dkappa - r1.dkappa) / (kn + P.kp);
  return Real(0.5) * fmax(es, ek);
}

/// The implicit return of a stiff substep in the p-q plane: the plastic multiplier x = d eps_d^p
/// (= d kappa) that brings the elastic trial (p_t, q_t) back onto the yield surface, with the
/// moduli K, G = rG K, the ratios M_p, M_pt and g(theta) frozen at the trial (backward Euler,
/// the flow evaluated at the end state, where q/(p g) = H):
///   q(x) = q_t - 3G x,   p(x) = p_t - K d x,   d = A_d (M_pt - H(x))          eqs. (13), (15)
///   H(x) = M_p (kappa + x)/(k_p + kappa + x)                                     eq. (14)
///   phi(x) = q(x) - H(x) g p(x) = 0                                             eq. (14)
/// (the flow is radial in the deviatoric plane, so the Lode angle stays the trial's).
struct StiffReturn {
  Real pt, qt, G3, KAd, Mp, Mpt, g, kappa, kp;  ///< KAd = K A_d
  SCREE_HD Real H(Real x) const { return Mp * (kappa + x) / (kp + kappa + x); }
  SCREE_HD Real p(Real x) const { return p(x, H(x)); }
  SCREE_HD Real phi(Real x) const {
    const Real h = H(x);
    return qt - G3 * x - h * g * p(x, h);
  }

 private:
  SCREE_HD Real p(Real x, Real h) const { return pt - KAd * (Mpt - h) * x; }
};

/// Whether the stiff remainder drem of an update from sig (void ratio e) may be done by the
/// implicit returns (integrate(), README step 5), as the margin by which the plastic contraction
/// outweighs the volumetric compression of drem; below 0: not at all.
/// - the state must be looser than critical, e >= e_c(p) (eq. 16): then M_pt >= M_c >= M_p
///   (eqs. 17-18) and the flow contracts (d >= 0, eq. 15) at every stress ratio the yield surface
///   allows, whatever the hardening (denser, dilatancy can build p by orders of magnitude along
///   the path, which returns with moduli frozen at the trial do not follow);
/// - margin = A_d (M_pt - M_p) eps_d(drem) / max(-tr drem, 0): the contraction at its slowest
///   over the elastic compression. The caller asks for 1 (p stays bounded: the balance of the
///   two near the apex, or a fall to it), and before it lets a return separate the point either
///   p <= p_min, where K ~ (p + p_min)^n hardly varies along the path and the frozen moduli are
///   all but exact, or 1.25 (where the two nearly balance at a larger p, whether the path falls
///   to the apex depends on how K varies along it).
template <class Pol = Production>
SCREE_HD inline Real stiff_return_margin(const Params& P, const Sym3& sig, Real e, const Sym3& drem) {
  const Real p = mean_pressure(sig);
  if (!(p > P.papex)) return -1;
  const Ratios R = ratios<Pol>(P, e, p);
  if (!(R.Mpt >= R.Mp)) return -1;  // denser than critical
  const Real contraction = P.Ad * (R.Mpt - R.Mp) * equivalent_deviatoric_strain(drem);
  const Real compression = fmax(-drem.trace(), Real(0));
  return contraction >= kUnbounded * compression ? kUnbounded : contraction / compression;
}
inline constexpr Real kStiffMargin = 1;        ///< stiff_return_margin() needed for the returns
inline constexpr Real kStiffApexMargin = 1.25;  ///< ... and for a return to separate a point at p > p_min

/// One stiff substep (integrate(), README step 5): the elastic predictor over d from sig at the
/// void ratio e_mid, then the implicit return above, solved for x in (0, q_t/3G) by the Pegasus
/// method (phi(0) > 0 outside the surface, phi(q_t/3G) = -H g p < 0 while p > 0), then the drift
/// correction of the substepping. Returns false (nothing changed) when the substep reaches the
/// apex: the trial separates, or p(x) would reach p_apex before q/(p g) comes down to H.
template <class Pol = Production>
SCREE_HD inline bool stiff_substep(const Params& P, Sym3& sig, Vars& v, Real e_mid, Real eb, const Sym3& d) {
  Sym3 st;
  if (!elastic_predictor<Pol>(P, sig, e_mid, d, st)) return false;
  const Invariants iv = invariants(st);
  if (!(iv.p > P.papex)) return false;
  const Ratios R = ratios<Pol>(P, eb, iv.p);
  const Real K = bulk_modulus<Pol>(P, eb, iv.p);
  const StiffReturn ret{iv.p, iv.q, 3 * P.rG * K, K * P.Ad, R.Mp, R.Mpt, lode_g<Pol>(P, iv.S), fmax(v.kappa, Real(0)),
                        P.kp};
  Real xa = 0, fa = ret.phi(0);
  Real x = 0;
  if (fa > 0) {  // plastic: locate the root of phi in (0, q_t/3G)
    Real xb = iv.q / ret.G3, fb = ret.phi(xb);
    if (!(fb < 0) || !(ret.p(xb) > P.papex)) return false;
    const Real tol = Real(1e-12) * (iv.q + ret.g * ret.Mp * iv.p);
    for (int it = 0; it < 100; ++it) {
      x = pegasus_point(xa, fa, xb, fb);
      const Real fx = ret.phi(x);
      if (fabs(fx) <= tol || fabs(xb - xa) <= Real(1e-15) * xb) break;
      pegasus_bracket(x, fx, xa, fa, xb, fb);
    }
    const Real pe = ret.p(x);
    if (!(pe > P.papex)) return false;
    const Real qe = iv.q - ret.G3 * x;
    st = from_p_s(pe, iv.s * (fmax(qe, Real(0)) / iv.q));
    const Real dil = P.Ad * (R.Mpt - ret.H(x));
    v.kappa += x;
    v.epsEq += x * sqrt(dil * dil * (Real(2) / 9) + 1);  // sqrt(2/3 m:m) dlambda, as plastic_rate()
  }
  sig = st;
  bool projected;
  yield_and_project<Pol>(P, sig, eb, v.kappa, true, projected);  // drift correction
  return true;
}

/// What stiff_remainder() did.
enum StiffOutcome { kStiffDone, kStiffApex, kStiffDeclined };

/// The remainder (T, 1] of the plastic part drem of an update in kReturnSubsteps stiff substeps
/// (integrate(), README step 5). kStiffDone: sig, v and T = 1 updated. kStiffApex: a return
/// reached the apex (allowed when may_separate); sig, v and T are those after the returns before
/// it (the caller separates the rest). kStiffDeclined: p grew along the returns beyond twice its
/// start (+ STOL s_e), where frozen moduli are not accurate, or a return reached the apex where
/// that is not certain; nothing changed (the caller goes on with Heun substeps).
template <class Pol = Production>
SCREE_HD inline StiffOutcome stiff_remainder(const Params& P, Sym3& sig, Vars& v, Real ope0, Real tr, Real alpha,
                                             Real& T, const Sym3& drem, bool may_separate) {
  Sym3 s = sig;
  Vars w = v;
  Real Ts = T;
  const Real pcap = 2 * mean_pressure(sig) + P.stol * P.serr;
  for (int j = 1; j <= kReturnSubsteps; ++j) {
    const Real Tn = j == kReturnSubsteps ? Real(1) : T + (1 - T) * j / kReturnSubsteps;
    const Real em = void_ratio_at(ope0, tr, alpha + (1 - alpha) * Real(0.5) * (Ts + Tn));
    const Real eb = void_ratio_at(ope0, tr, alpha + (1 - alpha) * Tn);
    if (!stiff_substep<Pol>(P, s, w, em, eb, drem * (Tn - Ts))) {
      if (!may_separate) return kStiffDeclined;
      sig = s;
      v = w;
      T = Ts;
      return kStiffApex;
    }
    if (mean_pressure(s) > pcap) return kStiffDeclined;
    Ts = Tn;
  }
  sig = s;
  v = w;
  T = 1;
  return kStiffDone;
}

}  // namespace scree::materials::simsand
