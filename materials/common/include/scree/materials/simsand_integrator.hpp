// SIMSAND-type critical-state frictional model: the stress update, integrate(), in stages.
//
// One update of the frictional stress over a strain increment, in five stages
// (materials/simsand/README.md, "Stress integration", says why each is as it is):
//   1. a stress-free start: the apex branch (integrate_at_apex);
//   2. the elastic trial, integrated exactly (elastic_trial): elastic or separating
//      increments end here;
//   3. the elastic fraction alpha up to the yield surface (elastic_fraction, start_plastic);
//   4. the plastic remainder in modified-Euler substeps with local error control and drift
//      correction (Sloan, Abbo & Sheng 2001), one substep() per attempt: a bound on the work
//      (bound_substep), the attempt and its error (heun_attempt), a path that reaches the
//      stress-free apex (toward_apex, apex_crossing), rejection or acceptance
//      (accept_substep), and stiff remainders by implicit returns (stiff_stage);
//   5. the remainder at the apex, and the guards on the result (finish).
// The pieces these stages call: simsand_substeps.hpp; the formulas: simsand_formulas.hpp.
// Units and signs: stresses in Pa, tension positive; p and q compression positive; strain
// increments tension positive.
//
// Device code: only <cmath> functions; no exceptions, allocation, recursion or lambdas. The
// stages are force-inlined (SCREE_INLINE): integrate() compiles to the one function it was
// written as.
#pragma once

#include <cmath>

#include "scree/core/config.hpp"
#include "scree/core/constants.hpp"
#include "scree/core/tensor.hpp"
#include "scree/materials/simsand_formulas.hpp"
#include "scree/materials/simsand_params.hpp"
#include "scree/materials/simsand_substeps.hpp"

// Diagnostics (off unless defined): with SCREE_SIMSAND_REPORT_SUBSTEPS = N, e.g. from the
// CMake option of that name in a diagnostic build, every update of integrate() that takes
// more than N substeps prints one line (printf, on the GPU too) with its count, its input
// stress, void ratio, kappa and strain increment at full precision: enough to replay it on
// the CPU and see where the substeps go. In GPU builds with SCREE_REPORT_CYCLES, every
// update notes its substeps and paths for the particle pass's report of slow warps
// (scree/core/report_cycles.hpp).
#if defined(SCREE_SIMSAND_REPORT_SUBSTEPS)
#include <cstdio>
#endif
#include "scree/core/report_cycles.hpp"

namespace scree::materials::simsand {

/// The opening of every stress update (integrate() and integrate_elastic() below): the void
/// ratios of the increment and the exact elastic trial from the start stress t.sig0.
/// Needs a finite t.sig0 and deps with p > p_apex (the caller handles the rest).
struct ElasticTrial {
  Real tr;         ///< tr deps (tension positive)
  Real ope0;       ///< 1 + e at the start
  Real e1;         ///< e at the end of the increment
  Real f0;         ///< yield function at the (projected) start stress (integrate() only)
  Sym3 sig0;       ///< start stress (integrate(): after the projection)
  Sym3 sig_tr;     ///< elastic trial stress at the end
  Real ftr;        ///< yield function at sig_tr (0 when it separates)
  bool separates;  ///< the trial ends in tension or at the apex: the point separates
  bool elastic;    ///< the whole increment is elastic: sig_tr is the answer
  PointRatios at0;  ///< g(theta) and M_p's parts at (sig0, e) (integrate() only)
};
template <class Pol = Production>
SCREE_HD inline void elastic_trial_from_start(const Params& P, const Vars& v, const Sym3& deps, ElasticTrial& t) {
  t.tr = deps.trace();
  t.ope0 = 1 + v.e;
  Real e_mid;
  void_ratios_mid_end(t.ope0, t.tr, e_mid, t.e1);
  // An extension whose elastic trial ends at the apex (p <= p_apex, where yield() no longer
  // bounds q) separates like one that would end in tension: otherwise a small stress rebuilt at
  // the apex could be pulled back to p ~ 0 with its deviator kept (q >> p).
  t.separates = !elastic_predictor<Pol>(P, t.sig0, e_mid, deps, t.sig_tr) ||
                !(mean_pressure(t.sig_tr) > P.papex);
  t.ftr = t.separates ? Real(0) : yield<Pol>(P, t.sig_tr, t.e1, v.kappa);
  t.elastic = !t.separates && t.ftr <= kFtol;
}
/// integrate()'s opening: the start stress first brought back onto the yield surface when it
/// lies outside (f0 > kFtol), e.g. an initial or prescribed stress from elsewhere.
template <class Pol = Production>
SCREE_HD inline ElasticTrial elastic_trial(const Params& P, const Sym3& sig, const Vars& v, const Sym3& deps) {
  ElasticTrial t;
  t.sig0 = sig;
  bool projected;
  t.f0 = yield_and_project<Pol>(P, t.sig0, v.e, v.kappa, false, projected, &t.at0);
  if (projected) t.f0 = 0;
  elastic_trial_from_start<Pol>(P, v, deps, t);
  return t;
}

/// The common cheap case of integrate(), alone: when the increment is elastic from a stressed
/// state, updates sig and v as integrate() would and returns true; otherwise (apex,
/// separation, plastic loading, non-finite input) returns false and changes nothing. The GPU
/// kernels run it first over all points and integrate() only over the others, so that the
/// common path runs in a fraction of the registers.
///
/// It takes the start stress as admissible (f <= kFtol) and skips integrate()'s start check,
/// a full yield evaluation and a large part of the elastic kernel's work: every state
/// integrate() leaves is admissible at its own (sig, e, kappa), and the next step starts
/// from the same values up to the round-off of the co-rotation. The two paths differ
/// only for a start outside the surface whose trial ends inside; then integrate() starts the
/// trial from the start scaled back onto the surface, this from the start itself, and both
/// end admissible. From an integrator's own state that needs a start f within round-off
/// above kFtol (1e-9): a difference of at most 1e-9 p g in q.
template <class Pol = Production>
SCREE_HD inline bool integrate_elastic(const Params& P, Sym3& sig, Vars& v, const Sym3& deps) {
  if (!finite_sym(sig) || !finite_sym(deps) || !(mean_pressure(sig) > P.papex)) return false;
  ElasticTrial t;
  t.sig0 = sig;
  elastic_trial_from_start<Pol>(P, v, deps, t);
  if (!t.elastic) return false;
  sig = t.sig_tr;
  v.e = t.e1;
  return true;
}

// ------------------------------------------------------------------ integrate() in stages

/// Stage 1, a stress-free start (p <= p_apex: after a separation or at a free surface): the
/// apex branch over the whole increment (apex_update), and the void ratio at its end.
template <class Pol>
SCREE_INLINE void integrate_at_apex(const Params& P, Sym3& sig, Vars& v, const Sym3& deps) {
  const Real tr = deps.trace();
  Real e_mid, e1;
  void_ratios_mid_end(1 + v.e, tr, e_mid, e1);
  apex_update<Pol>(P, sig, v, deps, e_mid, e1);
  v.e = e1;
}

/// Stage 3, the elastic fraction alpha of an increment whose elastic trial t is plastic (f > 0
/// at its end), from the start t.sig0 = sig:
/// - from inside the surface (f0 < 0): the Pegasus search of the crossing;
/// - from on it: 0 when the increment loads there (its rate, for the whole increment, is then
///   the first Euler rate: r1u, have_r1u), or, when it unloads first and re-yields later in
///   the increment (Sloan et al. 2001's check), the crossing after a point inside found on
///   the elastic path.
template <class Pol>
SCREE_INLINE Real elastic_fraction(const Params& P, const Sym3& sig, const Vars& v, const Sym3& deps,
                                   const ElasticTrial& t, Rate& r1u, bool& have_r1u) {
  Real alpha = 0;
  if (t.f0 < -kFtol) {
    alpha = yield_crossing<Pol>(P, sig, v.kappa, t.ope0, deps, 0, t.f0, 1, t.ftr);
  } else {
    Rate r0;
    const bool ok0 = plastic_rate<Pol>(P, sig, v.kappa, v.e, deps, t.ope0 * expm1(t.tr), r0, &t.at0);
    if (ok0 && r0.num >= 0) {
      r1u = r0;  // loading from the start: this is the first Euler rate
      have_r1u = true;
    } else if (ok0) {
      // elastic unloading first, re-yielding later in the increment: find a point inside
      Sym3 tmp;
      Real alo = -1, flo = 0;
      for (int j = 1; j < 10; ++j) {
        const Real a = Real(0.1) * j;
        const Real fa = elastic_path_yield<Pol>(P, sig, v.kappa, t.ope0, deps, a, tmp);
        if (fa < -kFtol) {
          alo = a;
          flo = fa;
        } else if (alo > 0) {
          break;
        }
      }
      if (alo > 0) alpha = yield_crossing<Pol>(P, sig, v.kappa, t.ope0, deps, alo, flo, 1, t.ftr);
    }
  }
  return alpha;
}

/// The plastic part of an update (stage 4): where the substepping is in the increment and
/// what it carries from one substep to the next. Set up by start_plastic() alone (the starting
/// values there, none here): a default held from the declaration of an Integration would stay
/// live through the elastic trial on every path, and the kernels that run integrate() whole
/// would spill.
struct Substepping {
  Real ope0;    ///< 1 + e at the start of the increment
  Real tr;      ///< tr deps (tension positive)
  Real alpha;   ///< elastic fraction of the increment (stage 3)
  Sym3 drem;    ///< the plastic part of the increment, (1 - alpha) deps
  Real snear;   ///< the local error the control accepts near zero stress, where the floor s_e
                ///< makes it absolute: STOL x s_e (0.1 Pa with STOL = 1e-3) [Pa]
  Real T;                ///< fraction of drem done
  Real dT;               ///< size of the next substep, a fraction of drem
  Real dT_relaxed;       ///< smallest substep once the error control is relaxed (-1: not yet)
  Real ea;               ///< e at the start of the substep (the last accepted substep's end)
  Rate r1u;              ///< rate at the start of the current substep for the whole remaining
  bool have_r1u;         ///< increment (linear in it: reused, scaled, after a rejection)
  PointRatios at;        ///< g(theta) and M_p's parts at (sig, ea) from the last drift correction
  int n;                 ///< substep attempts and rate evaluations (the bound on the work)
  bool at_apex;          ///< the path has reached the stress-free apex: the remainder is done there
  bool stiff_tried;      ///< implicit returns tried for the remainder (README step 5), once
  bool apex_searched;    ///< the crossing of the apex searched (diagnostics only)

  /// e at the fraction x of the plastic part drem.
  SCREE_HD Real void_ratio(Real x) const { return void_ratio_at(ope0, tr, alpha + (1 - alpha) * x); }
};

/// Stage 3 completed: the elastic fraction (elastic_fraction), sig moved along the elastic
/// path to the crossing, and the substepping of the plastic part set up from there.
template <class Pol>
SCREE_INLINE Substepping start_plastic(const Params& P, Sym3& sig, const Vars& v, const Sym3& deps,
                                       const ElasticTrial& t) {
  Substepping s;
  s.ope0 = t.ope0;
  s.tr = t.tr;
  s.T = 0;
  s.dT = 1;
  s.dT_relaxed = -1;
  s.have_r1u = false;
  s.n = 0;
  s.at_apex = false;
  s.stiff_tried = false;
  s.apex_searched = false;
  s.alpha = elastic_fraction<Pol>(P, sig, v, deps, t, s.r1u, s.have_r1u);
  if (s.alpha > 0) {
    Sym3 sa;
    if (elastic_predictor<Pol>(P, sig, void_ratio_at(s.ope0, s.tr, Real(0.5) * s.alpha), deps * s.alpha, sa)) sig = sa;
  }
  s.drem = deps * (1 - s.alpha);
  s.ea = void_ratio_at(s.ope0, s.tr, s.alpha);
  s.snear = P.stol * P.serr;
  return s;
}

/// A stiff remainder (README step 5): after kStiffAfter attempts, the substep the error control
/// asks for is set by the elastic stiffness (about p/(3G |de_d|): hundreds of substeps near the
/// apex, or where M_p is tiny at a large void ratio), not by the curvature of the path; the
/// remainder is done by implicit returns where stiff_return_margin() allows them. Returns
/// true when they finished the increment (or reached the apex: s.at_apex); false to go on
/// with Heun substeps.
template <class Pol>
SCREE_INLINE bool stiff_stage(const Params& P, Sym3& sig, Vars& v, Substepping& s) {
  if (!(Pol::stiff_returns && !s.stiff_tried && s.n > kStiffAfter && 1 - s.T > kStiffRemaining * s.dT)) return false;
  s.stiff_tried = true;
  const Real margin = stiff_return_margin<Pol>(P, sig, s.ea, s.drem);
  const StiffOutcome o = margin >= kStiffMargin
                             ? stiff_remainder<Pol>(P, sig, v, s.ope0, s.tr, s.alpha, s.T, s.drem,
                                                    margin >= kStiffApexMargin || mean_pressure(sig) <= P.pmin)
                             : kStiffDeclined;
  if (o == kStiffApex) s.at_apex = true;
  return o != kStiffDeclined;
}

/// Bounded work (`maxSubsteps`, P.nmax = N): after N substeps the error control is switched
/// off and the substep is not allowed below 1/N of what then remained; after 3N the
/// remainder is done in one step. So an update takes at most 3N + 1 substeps, whatever its
/// increment. Returns whether the control is relaxed.
SCREE_INLINE bool bound_substep(const Params& P, Substepping& s) {
  const bool relaxed = s.n > P.nmax;
  if (relaxed && s.dT_relaxed < 0) s.dT_relaxed = (1 - s.T) / P.nmax;
  if (relaxed) s.dT = fmin(fmax(s.dT, s.dT_relaxed), 1 - s.T);
  if (s.n > 3 * P.nmax) s.dT = 1 - s.T;
  return relaxed;
}

/// Whether R is a local error estimate rather than the mark of none (kUnbounded: a rate failed
/// or the end state lies beyond the apex).
SCREE_HD inline bool estimated(Real R) { return R < Real(1e299); }

/// One attempted Heun substep: its two rates, its end state (sn, kn), its local error R and
/// whether the error control rejects it.
struct Attempt {
  Rate r1, r2;
  Sym3 sn;
  Real kn;
  Real R;
  bool reject;
};

/// A Heun substep of size s.dT from (sig, v.kappa), ending at the void ratio eb. Its error
/// R is kUnbounded when a rate fails or the end state is at or beyond the apex, unless the
/// error test rejects it anyway away from the apex: a Heun end state beyond the apex from a
/// substep whose error fails the test does not say that the path reaches the apex, only that
/// the substep is too coarse (the Euler rate, extrapolated, overshoots): it is rejected like
/// any other (README step 4), and no search of a crossing is spent on it.
template <class Pol>
SCREE_INLINE Attempt heun_attempt(const Params& P, const Sym3& sig, const Vars& v, const Substepping& s, Real eb,
                                  bool relaxed) {
  Attempt a;
  a.sn = sig;
  a.kn = v.kappa;
  a.R = kUnbounded;
  const bool ok =
      s.have_r1u && heun_substep<Pol>(P, sig, v.kappa, s.r1u, s.drem, s.dT, eb, eb - s.ea, a.r1, a.r2, a.sn, a.kn);
  if (ok) a.R = heun_error(P, a.r1, a.r2, a.sn, a.kn);
  a.reject = a.R > P.stol && !relaxed && s.dT > kMinSubstep;
  if ((!ok || !(mean_pressure(a.sn) > P.papex)) && !(a.reject && estimated(a.R) && norm(sig) > s.snear))
    a.R = kUnbounded;
  return a;
}

/// Take the attempted substep a of size x (a fraction of drem) ending at the void ratio e_end.
SCREE_INLINE void take_substep(Sym3& sig, Vars& v, Substepping& s, const Attempt& a, Real x, Real e_end) {
  sig = a.sn;
  v.kappa = a.kn;
  v.epsEq += Real(0.5) * (a.r1.deq + a.r2.deq);
  s.T += x;
  s.ea = e_end;
}

/// Where the apex lies within the substep (ph, the Heun end pressure, <= p_apex): Pegasus on
/// the substep size x in (0, dT) with the pressure of the Heun end state as the function,
/// aiming a little above zero (pt). A Heun state within STOL x s_e of the apex whose local
/// error passes the usual test is accepted, and the remainder done at the apex (returns true,
/// s.at_apex); one whose error fails gives the next substep size (Sloan's rule); with no such
/// state after kApexIter evaluations the substepping goes on from the largest size with p > pt
/// at its end. Each evaluation counts as a rejected substep (bounded work).
template <class Pol>
SCREE_INLINE bool apex_crossing(const Params& P, Sym3& sig, Vars& v, Substepping& s, Attempt& a, Real ph,
                                bool relaxed) {
  const Real pt = P.papex + Real(0.25) * s.snear;
  Real xa = 0, ha = mean_pressure(sig) - pt, xb = s.dT, hb = ph - pt, xpos = 0, xnext = -1;
  s.apex_searched = true;
  for (int it = 0; it < kApexIter; ++it) {
    ++s.n;  // one rate evaluation, like a rejected substep (bounded work)
    const Real x = pegasus_point(xa, ha, xb, hb);
    if (!(x > 0 && x < s.dT)) break;
    const Real ex = s.void_ratio(s.T + x);
    const bool okx = heun_substep<Pol>(P, sig, v.kappa, s.r1u, s.drem, x, ex, ex - s.ea, a.r1, a.r2, a.sn, a.kn);
    const Real px = mean_pressure(a.sn);
    if (okx && px > P.papex) {
      const Real Rx = heun_error(P, a.r1, a.r2, a.sn, a.kn);
      if (Rx > P.stol && !relaxed) {
        // a substep of this size is too coarse to say where the path meets the apex (its
        // Euler rate, extrapolated, overshoots), at the crossing or short of it: the next
        // size by the error control, as after any rejection (README step 4)
        xnext = x * fmax(substep_factor(P, Rx), Real(0.1));
        break;
      }
      if (norm(a.sn) <= s.snear) {  // the crossing, to within what the error control accepts
        take_substep(sig, v, s, a, x, ex);
        s.at_apex = true;
        return true;
      }
      xpos = fmax(xpos, x);
    }
    pegasus_bracket(x, px - pt, xa, ha, xb, hb);
  }
  s.dT = fmax(xnext > 0 ? xnext : (xpos > 0 ? xpos : Real(0.1) * s.dT), Real(1e-3) * kMinSubstep);
  return false;
}

/// An attempt without an error estimate (a.R = kUnbounded): p would drop to zero within the
/// substep (Heun or Euler end state at p <= p_apex), the path reaches the stress-free apex,
/// or a rate could not be evaluated. Not a tenth of the substep, regrowing by 1.1 per
/// accepted one: grains at a fraction of a pascal that load towards the apex took thousands
/// of substeps in one update that way and separated in the end all the same (and on the GPU
/// a step lasts as long as its slowest update). Instead the point finishes at the apex when
/// it is already within STOL x s_e of it, or the crossing is located (apex_crossing). Returns
/// true when the substepping stops there (s.at_apex); false to go on with the next s.dT.
template <class Pol>
SCREE_INLINE bool toward_apex(const Params& P, Sym3& sig, Vars& v, Substepping& s, Attempt& a, bool relaxed) {
  const Real ph = mean_pressure(a.sn);
  if (!s.have_r1u || (ph <= P.papex && (norm(sig) <= s.snear || s.n > 3 * P.nmax))) {
    // - already within the error the control accepts per substep (STOL x s_e) of the
    //   apex, and heading there: finish at the apex (also when the rates fail at sig, or
    //   when the work bound is spent). Only here, on the way to the apex: a grain being
    //   compressed from a small stress takes the ordinary path and builds stress.
    s.at_apex = true;
    return true;
  }
  if (!(ph <= P.papex)) {  // a rate could not be evaluated (not finite): smaller substep
    if (s.dT > kMinSubstep && s.n <= 3 * P.nmax) {
      s.dT = fmax(Real(0.1) * s.dT, kMinSubstep);
      return false;
    }
    s.at_apex = true;
    return true;
  }
  // - otherwise locate the crossing
  return apex_crossing<Pol>(P, sig, v, s, a, ph, relaxed);
}

/// Accept the attempt: take it, correct the drift back onto the yield surface (which also
/// evaluates g(theta) and M_p for the next substep's first rate, s.at), and size the next
/// substep by Sloan et al. (2001)'s factor, at most 1.1. Returns true when the increment is done.
template <class Pol>
SCREE_INLINE bool accept_substep(const Params& P, Sym3& sig, Vars& v, Substepping& s, const Attempt& a, Real eb) {
  take_substep(sig, v, s, a, s.dT, eb);
  s.have_r1u = false;
  bool projected;
  yield_and_project<Pol>(P, sig, eb, v.kappa, true, projected, &s.at);  // drift correction
  if (s.T >= 1 - Real(1e-12)) return true;
  const Real fac = a.R > 0 ? fmin(substep_factor(P, a.R), Real(1.1)) : Real(1.1);
  s.dT = fmin(fmax(s.dT * fac, kMinSubstep), 1 - s.T);
  return false;
}

/// Stage 4, one attempt of the plastic part: the stiff remainder, the bound on the work, the
/// first rate (unless a rejection left it), the Heun attempt, then the apex, a rejection
/// (smaller substep) or the acceptance. Returns false when the substepping stops.
template <class Pol>
SCREE_INLINE bool substep(const Params& P, Sym3& sig, Vars& v, Substepping& s) {
  ++s.n;
  if (stiff_stage<Pol>(P, sig, v, s)) return false;
  const bool relaxed = bound_substep(P, s);
  const Real eb = s.void_ratio(s.T + s.dT);
  if (!s.have_r1u)
    s.have_r1u = plastic_rate<Pol>(P, sig, v.kappa, s.ea, s.drem, (1 + s.ea) * expm1(s.tr * (1 - s.alpha)), s.r1u,
                                   &s.at);
  Attempt a = heun_attempt<Pol>(P, sig, v, s, eb, relaxed);
  if (!estimated(a.R)) return !toward_apex<Pol>(P, sig, v, s, a, relaxed);
  if (a.reject) {  // smaller substep (Sloan et al. 2001)
    s.dT = fmax(s.dT * fmax(substep_factor(P, a.R), Real(0.1)), kMinSubstep);
    return true;
  }
  return !accept_substep<Pol>(P, sig, v, s, a, eb);
}

/// Stage 5: the remainder of the increment at the apex, when the path reached it. The point
/// separates (sigma = 0, the deviatoric strain of the remainder is plastic: kappa and epsEq
/// grow); the next update starts from the apex branch. Not the apex branch over the
/// remainder: its one elastic trial from zero rebuilds K |tr deps| at once where the
/// converged path (many small increments) stays at the apex, dragged back by the
/// contractive flow. Then the void ratio at the end (e1) and a defined state whatever
/// happened: finite, no tension.
SCREE_INLINE void finish(Sym3& sig, Vars& v, const Substepping& s, Real e1) {
  // paths: 1 implicit returns tried, 2 the apex crossing searched, 4 the remainder at the apex
  diag::report_work(unsigned(s.n), (s.stiff_tried ? 1u : 0u) | (s.apex_searched ? 2u : 0u) | (s.at_apex ? 4u : 0u));
  if (s.at_apex) separate(sig, v, s.drem, 1 - fmin(fmax(s.T, Real(0)), Real(1)));
  v.e = e1;
  if (!finite_sym(sig) || !(mean_pressure(sig) >= 0)) sig = Sym3::zero();
}

#if defined(SCREE_SIMSAND_REPORT_SUBSTEPS)
/// The diagnostic line of an update of more than SCREE_SIMSAND_REPORT_SUBSTEPS substeps (top).
SCREE_HD inline void report_substeps(const Substepping& s, const Sym3& sig_in, const Vars& v_in, const Sym3& deps) {
  if (s.n > SCREE_SIMSAND_REPORT_SUBSTEPS)
    printf("simsand-substeps %d apex %d sig %.17g %.17g %.17g %.17g %.17g %.17g e %.17g kappa %.17g "
           "deps %.17g %.17g %.17g %.17g %.17g %.17g\n",
           s.n, s.at_apex ? 1 : 0, sig_in[0], sig_in[1], sig_in[2], sig_in[3], sig_in[4], sig_in[5], v_in.e,
           v_in.kappa, deps[0], deps[1], deps[2], deps[3], deps[4], deps[5]);
}
#endif

/// An update of the frictional model in flight, in turns: integrate_begin() (stages 1-3),
/// integrate_turn() while it asks for more (stage 4, one substep() each), integrate_end()
/// (stage 5). integrate() runs them in sequence; a GPU kernel interleaves the turns of many
/// points so that a lane whose point is done takes the next one (particle_pass.hpp,
/// DeferredStress) while the others still substep: each point's arithmetic the same.
struct Integration {
  Sym3 sig;       ///< the stress (tension positive) [Pa]: the start, then the result
  Vars v;         ///< the internal variables: the start, then the result
  Substepping s;  ///< the plastic part (stage 4), when there is one
  Real e1;       ///< e at the end of the increment (with a plastic part)
  bool plastic;  ///< stage 4 was set up: turns to run and stage 5 to finish
#if defined(SCREE_SIMSAND_REPORT_SUBSTEPS)
  Sym3 sig_in, deps_in;
  Vars v_in;
#endif
};

/// Stages 1-3 of an update from u.sig, u.v over deps. Returns whether the plastic part
/// remains (integrate_turn until it returns false, then integrate_end); otherwise the result
/// is in u already (integrate_end leaves it).
template <class Pol = Production>
SCREE_INLINE bool integrate_begin(const Params& P, Integration& u, const Sym3& deps) {
  u.plastic = false;
  if (!finite_sym(u.sig)) u.sig = Sym3::zero();
  if (!finite_sym(deps)) {  // nothing sensible to integrate
    u.v.e = fmax(u.v.e, Real(1e-6));
    return false;
  }
#if defined(SCREE_SIMSAND_REPORT_SUBSTEPS)
  u.sig_in = u.sig;
  u.v_in = u.v;
  u.deps_in = deps;
#endif
  if (!(mean_pressure(u.sig) > P.papex)) {  // 1. a stress-free point
    integrate_at_apex<Pol>(P, u.sig, u.v, deps);
    return false;
  }
  const ElasticTrial t = elastic_trial<Pol>(P, u.sig, u.v, deps);  // 2. the elastic trial
  u.sig = t.sig0;
  if (t.separates) {
    separate(u.sig, u.v, deps, 1);
    u.v.e = t.e1;
    return false;
  }
  if (t.elastic) {  // elastic: the common cheap path
    u.sig = t.sig_tr;
    u.v.e = t.e1;
    return false;
  }
  u.s = start_plastic<Pol>(P, u.sig, u.v, deps, t);  // 3. the elastic fraction
  u.e1 = t.e1;
  u.plastic = true;
  return true;
}

/// Stage 4, one turn: one substep() of the plastic part. Returns whether more remain.
template <class Pol = Production>
SCREE_INLINE bool integrate_turn(const Params& P, Integration& u) {
  return substep<Pol>(P, u.sig, u.v, u.s) && u.s.T < 1;
}

/// Stage 5 when there was a plastic part (finish); returns whether the update reached the
/// bound on its work (bound_substep: more than `maxSubsteps` substeps, the rest without
/// error control).
SCREE_INLINE bool integrate_end(const Params& P, Integration& u) {
  if (!u.plastic) return false;
#if defined(SCREE_SIMSAND_REPORT_SUBSTEPS)
  report_substeps(u.s, u.sig_in, u.v_in, u.deps_in);
#endif
  finish(u.sig, u.v, u.s, u.e1);  // 5. the remainder at the apex, a defined state
  return u.s.n > P.nmax;
}

/// One stress update of the frictional model: sig (tension positive) and the internal
/// variables v over the strain increment deps. Always leaves a defined state: p >= 0,
/// no tension, finite values. Returns whether the update reached the bound on its work
/// (bound_substep: more than `maxSubsteps` substeps, the rest without error control).
/// The same stages as integrate_begin, integrate_turn and integrate_end in sequence, and the
/// same result to the bit (tests/unit/materials/test_robustness.cpp, UpdatesInTurns...);
/// written whole because the kernels that run it whole compile it with half the spills that
/// the sequence through an Integration takes (measure/ptx-line-counts.sh).
template <class Pol = Production>
SCREE_HD inline bool integrate(const Params& P, Sym3& sig, Vars& v, const Sym3& deps) {
  if (!finite_sym(sig)) sig = Sym3::zero();
  if (!finite_sym(deps)) {  // nothing sensible to integrate
    v.e = fmax(v.e, Real(1e-6));
    return false;
  }
#if defined(SCREE_SIMSAND_REPORT_SUBSTEPS)
  const Sym3 sig_in = sig;
  const Vars v_in = v;
#endif
  if (!(mean_pressure(sig) > P.papex)) {  // 1. a stress-free point
    integrate_at_apex<Pol>(P, sig, v, deps);
    return false;
  }
  const ElasticTrial t = elastic_trial<Pol>(P, sig, v, deps);  // 2. the elastic trial
  sig = t.sig0;
  if (t.separates) {
    separate(sig, v, deps, 1);
    v.e = t.e1;
    return false;
  }
  if (t.elastic) {  // elastic: the common cheap path
    sig = t.sig_tr;
    v.e = t.e1;
    return false;
  }
  Substepping s = start_plastic<Pol>(P, sig, v, deps, t);  // 3. the elastic fraction
  while (s.T < 1)                                          // 4. the plastic part
    if (!substep<Pol>(P, sig, v, s)) break;
#if defined(SCREE_SIMSAND_REPORT_SUBSTEPS)
  report_substeps(s, sig_in, v_in, deps);
#endif
  finish(sig, v, s, t.e1);  // 5. the remainder at the apex, a defined state
  return s.n > P.nmax;
}

}  // namespace scree::materials::simsand
