// The fast evaluation of the granular models (Feng et al. 2025) against the straightforward one.
//
// The policy simsand::ExactPowers evaluates every power with pow(), as the model was first
// written; simsand::Production takes the exponents 1/2, 2 and 1/4 by sqrt and products and
// the void-ratio powers of eqs. (17)-(18) from one logarithm (simsand_model.hpp). Both
// compute the same function; they differ by a few ulps per power.
//
// What "the same within round-off" can mean for this integrator: at low mean stress with
// a strain increment far larger than the stress (a point being sheared apart at a free
// surface), the substepping runs at its smallest step and its decisions (separate or
// not, accept or reject a substep) flip under a 1-ulp change of the input, and the
// result changes by up to the stress itself. So the test asks two things of random
// states: (1) most results agree to 1e-12; (2) the fast path departs from the reference
// no more often, at each size of difference, than the reference departs from itself when
// its input stress is perturbed by one ulp. The elastic-plastic paths of the element
// tests (smooth loading) must agree to 1e-9.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "phaseTransition/PhaseTransition.hpp"
#include "scree/materials/simsand_model.hpp"

using namespace scree;
using namespace scree::materials;

namespace {

simsand::Params collapse_f() {  // Table 3, column collapse: n = 0.5
  return simsand::make_params({.K0 = 120, .nu = 0.2, .n = 0.5, .pat = 101300, .phic_deg = 19.8, .eref = 0.977,
                               .lambda = 0.0596, .xi = 0.365, .Ad = 0.7, .kp = 0.0044, .np = 2.4, .nd = 2.9,
                               .pmin = 1.0, .stol = 1e-4, .lode = true});
}
simsand::Params table1_f() {  // Table 1: n = 0.6 (no sqrt shortcut for K)
  return simsand::make_params({.K0 = 150, .nu = 0.22, .n = 0.6, .pat = 101300, .phic_deg = 30, .eref = 0.937,
                               .lambda = 0.022, .xi = 0.71, .Ad = 4, .kp = 0.001, .np = 1, .nd = 1, .pmin = 1.0,
                               .stol = 1e-4, .lode = true});
}
using simsand::ExactPowers;
kt::Params collapse_c(double zeta1 = 1) {  // Table 3, column collapse: e_sd = 0.62
  const double Vsd = 1 / 1.62, Vm = 0.4;
  return kt::make_params(kt::Constants{.rho_p = 2650,
                                       .d = 1.25e-3,
                                       .Vsd = Vsd,
                                       .Vm = Vm,
                                       .eps = kt::effective_restitution(0.6, 0.2),
                                       .Vcap = kt::cap_solid_fraction(Vsd, Vm, 1000),
                                       .Vmin = 1e-3,
                                       .zeta1 = zeta1});
}

/// The collisional coefficients written out term by term as Feng et al. 2025 print them
/// (eqs. 20-28, (A4)-(A9), (B11)-(B14)), with the corrections from Garzo & Dufty 1999 that
/// kinetic_theory.hpp documents: G = V g0, gamma* with V G, Gamma0 with V^2, (B14) with -19.
/// Every quotient is taken where it appears, nothing is prepared: an independent check of
/// the prepared factors of kt::make_params and of kt::coefficients.
kt::Coefficients term_by_term(const kt::Constants& P, double V) {
  kt::Coefficients c{};
  const double e = P.eps, e2 = e * e, e3 = e2 * e, pi = 3.14159265358979323846, sqrt_pi = std::sqrt(pi);
  c.V = V;
  const double cs = (2 - V) / (2 * std::pow(1 - V, 3));  // eq. (25)
  const double f = V < P.Vm ? 1.0
                            : 1 - std::pow((V - P.Vm) / (P.Vsd - P.Vm), 2);  // eq. (26), the printed form
  c.g0 = f * cs + (1 - f) * 2 / (P.Vsd - V);                                  // eq. (25)
  c.G = V * c.g0;                                                             // eq. (23)
  c.p_star = 1 + 2 * (1 + e) * c.G;                                           // eq. (20) with (A1)
  c.cstar = 32 * (1 - e) * (1 - 2 * e2) / (81 - 17 * e + 30 * e2 * (1 - e));  // (A9)
  c.zeta0 = 5.0 / 12 * c.g0 * (1 - e2) * (1 + 3 * c.cstar / 32);              // (A7)
  const double nu_eta = c.g0 * (1 - 0.25 * (1 - e) * (1 - e)) * (1 - c.cstar / 64);  // (A8)
  const double eta_k = (1 - 0.4 * (1 + e) * (1 - 3 * e) * c.G) / (nu_eta - 0.5 * c.zeta0);  // (A6)
  c.gam_star = 128 / (5 * pi) * V * c.G * (1 + e) * (1 - c.cstar / 32);                 // (A5)
  c.eta_star = eta_k * (1 + 0.8 * c.G * (1 + e)) + 0.6 * c.gam_star;                      // (A4)
  const double eta0 = 5 * sqrt_pi / 96 * P.rho_p * P.d;
  c.eta_hat = eta0 * c.eta_star;                                                          // eq. (21)
  c.gam_hat = eta0 * c.gam_star;                                                          // eq. (22)
  c.p_hat = P.rho_p * V * c.p_star;                                                       // eq. (20)
  c.diss_hat = 144 / (5 * sqrt_pi) * P.rho_p * V * V * c.zeta0 / P.d;                     // eq. (28)
  if (P.zeta1 > 0) {
    const double lam = 0.375 * ((1 - e) * (5 * e2 + 4 * e - 1) + c.cstar / 12 * (159 * e + 3 * e2 - 19 - 15 * e3));
    const double nu_gam = (1 + e) / 48 * c.g0 *
                          (128 - 96 * e + 15 * e2 - 15 * e3 + c.cstar / 64 * (15 * e3 - 15 * e2 + 498 * e - 434));
    const double N = 4.0 / 15 * lam * c.G + (c.p_star - 1) * (2.0 / 3 - e) * c.cstar;             // (B12)
    const double Dn = 0.5 * c.zeta0 + nu_gam + 5.0 / 64 * c.cstar * (1 + 3 * c.cstar / 64) * c.g0 * (1 - e2);
    const double br = -(1 - e) * (c.p_star - 1) + 5.0 / 32 * (1 - e2) * (1 + 3 * c.cstar / 64) * c.g0 * (N / Dn);
    c.div_hat = 1.5 * P.rho_p * V * br;                                                    // (B11) in eq. (28)
  }
  c.energy = 1.5 * P.rho_p * V;  // eq. (27)
  return c;
}

/// A random admissible starting point and strain increment: p log-uniform in [1e-3, 1e5] Pa,
/// stress ratio up to 1.6, any Lode angle, on or inside the yield surface, increments of
/// 1e-7 to 3e-3 in any direction (plane strain half of the time).
struct Sample {
  Sym3 sig, deps;
  simsand::Vars v;
};
Sample random_sample(std::mt19937_64& r, const simsand::Params& P) {
  std::uniform_real_distribution<double> U(0, 1);
  Sample s;
  const double p = std::pow(10.0, -3 + 8 * U(r));
  const double e = 0.6 + 0.5 * U(r);
  Sym3 dev = Sym3::zero();
  for (int k = 0; k < 6; ++k) dev[k] = U(r) - 0.5;
  if (U(r) < 0.5) dev[4] = dev[5] = 0;
  dev = deviator(dev);
  const double eta = 1.6 * U(r);
  s.sig = simsand::from_p_s(p, dev * (eta * p / deviatoric_stress(dev)));
  s.v = simsand::Vars{e, 0.3 * U(r) * U(r), 0.1 * U(r)};
  if (U(r) < 0.5) s.v = simsand::initial_vars<ExactPowers>(P, s.sig, e);  // on the surface (the reference's)
  for (int k = 0; k < 6; ++k) s.deps[k] = U(r) - 0.5;
  if (U(r) < 0.5) s.deps[2] = s.deps[4] = s.deps[5] = 0;
  s.deps = s.deps * std::pow(10.0, -7 + 4.5 * U(r));
  return s;
}

double rel_diff(const Sym3& a, const Sym3& b) { return norm(a - b) / std::max(norm(b), 1.0); }

struct Census {
  static constexpr double kLevels[4] = {1e-12, 1e-9, 1e-6, 1e-3};
  long over[4] = {0, 0, 0, 0};
  void add(double d) {
    for (int i = 0; i < 4; ++i) over[i] += d > kLevels[i];
  }
};

void expect_fast_within_reference_sensitivity(const simsand::Params& P) {
  std::mt19937_64 r(2026);
  const long n = 20000;
  Census fast_vs_ref, ref_vs_ref;
  long differ = 0;  // updates whose bits differ: the policies must be two evaluations
  for (long i = 0; i < n; ++i) {
    const Sample s = random_sample(r, P);
    Sym3 a = s.sig, b = s.sig, c = s.sig;
    simsand::Vars va = s.v, vb = s.v, vc = s.v;
    simsand::integrate(P, a, va, s.deps);
    simsand::integrate<ExactPowers>(P, b, vb, s.deps);
    for (int k = 0; k < 6; ++k) c[k] = std::nextafter(c[k], 2 * c[k] - 1);  // one ulp (away from 0.5 c)
    simsand::integrate<ExactPowers>(P, c, vc, s.deps);
    ASSERT_TRUE(std::isfinite(norm(a)) && std::isfinite(va.e) && std::isfinite(va.kappa)) << "sample " << i;
    fast_vs_ref.add(std::max(rel_diff(a, b), std::fabs(va.kappa - vb.kappa) / (vb.kappa + P.kp)));
    ref_vs_ref.add(std::max(rel_diff(c, b), std::fabs(vc.kappa - vb.kappa) / (vb.kappa + P.kp)));
    EXPECT_NEAR(va.e, vb.e, 1e-12 * vb.e) << "sample " << i;  // e follows the volume only
    differ += norm(a - b) != 0;
  }
  EXPECT_GT(differ, n / 100) << "Production and ExactPowers gave the same bits: not two evaluations";
  EXPECT_LT(fast_vs_ref.over[0], n / 50) << "more than 2% of the updates differ by more than 1e-12";
  for (int l = 1; l < 4; ++l)
    EXPECT_LE(fast_vs_ref.over[l], 2 * ref_vs_ref.over[l] + 5)
        << "differences above " << Census::kLevels[l] << ": fast path " << fast_vs_ref.over[l]
        << ", the reference under a 1-ulp input change " << ref_vs_ref.over[l];
}

}  // namespace

TEST(MaterialFastPath, SimsandRandomStatesColumnCollapseParameters) {
  expect_fast_within_reference_sensitivity(collapse_f());
}

TEST(MaterialFastPath, SimsandRandomStatesTable1Parameters) {
  expect_fast_within_reference_sensitivity(table1_f());
}

// A smooth loading path (drained simple shear at constant vertical stress is not needed:
// isochoric simple shear from a K0 state through peak to the critical state, 2000 steps)
// is integrated alike by both to 1e-9.
TEST(MaterialFastPath, SimsandSimpleShearPathAgrees) {
  for (bool table1 : {false, true}) {
    const simsand::Params P = table1 ? table1_f() : collapse_f();
    Sym3 sa{{-5e3, -1e4, -5e3, 0, 0, 0}}, sb = sa;
    simsand::Vars va = simsand::initial_vars(P, sa, 0.8), vb = simsand::initial_vars<ExactPowers>(P, sb, 0.8);
    Sym3 d = Sym3::zero();
    d[3] = 0.5e-4;
    for (int i = 0; i < 2000; ++i) {
      simsand::integrate(P, sa, va, d);
      simsand::integrate<ExactPowers>(P, sb, vb, d);
    }
    EXPECT_LT(rel_diff(sa, sb), 1e-9) << (table1 ? "table 1" : "table 3");
    EXPECT_NEAR(va.kappa, vb.kappa, 1e-9 * vb.kappa);
    EXPECT_GT(vb.kappa, 0.01);  // it did go plastic
  }
}

// phaseTransition::update with both evaluations (the collisional part is the same code),
// from random frictional states with a granular temperature, at dt = 1e-5 s.
TEST(MaterialFastPath, PhaseTransitionRandomStates) {
  const PhaseTransition::Params P{collapse_f(), collapse_c(), 0.95, 1e-12};
  std::mt19937_64 r(7);
  std::uniform_real_distribution<double> U(0, 1);
  const long n = 5000;
  Census fast_vs_ref, ref_vs_ref;
  for (long i = 0; i < n; ++i) {
    const Sample s = random_sample(r, P.f);
    PhaseTransition::State st{};
    st.sigf = s.sig;
    st.e = s.v.e;
    st.kappa = s.v.kappa;
    st.epsEq = s.v.epsEq;
    st.T = std::pow(10.0, -12 + 12 * U(r));
    StrainIncrement inc{s.deps, Spin3{1e-3 * (U(r) - 0.5), 0, 0}, 1e-5, 1};
    PhaseTransition::State a = st, b = st, c = st;
    for (int k = 0; k < 6; ++k) c.sigf[k] = std::nextafter(c.sigf[k], 2 * c.sigf[k] - 1);
    Sym3 sa = Sym3::zero(), sb = sa, sc = sa;
    PhaseTransition::update(P, a, sa, inc);
    PhaseTransition::update_with<ExactPowers>(P, b, sb, inc);
    PhaseTransition::update_with<ExactPowers>(P, c, sc, inc);
    fast_vs_ref.add(std::max(rel_diff(sa, sb), std::fabs(a.T - b.T) / (b.T + 1e-12)));
    ref_vs_ref.add(std::max(rel_diff(sc, sb), std::fabs(c.T - b.T) / (b.T + 1e-12)));
  }
  EXPECT_LT(fast_vs_ref.over[0], n / 50);
  for (int l = 1; l < 4; ++l)
    EXPECT_LE(fast_vs_ref.over[l], 2 * ref_vs_ref.over[l] + 5)
        << "differences above " << Census::kLevels[l] << ": fast " << fast_vs_ref.over[l] << ", reference +1 ulp "
        << ref_vs_ref.over[l];
}

// kt::coefficients (the prepared factors of kt::make_params) against the functions written
// out term by term, on both branches of g0 (eq. 26), with and without zeta1: equal to
// round-off. And one point by hand: at V = 0.3 < V_m, g0 is Carnahan-Starling,
// g0 = 1.7/(2 0.7^3) = 2.478134..., so p* = 1 + 2 (1 + eps) 0.3 g0.
TEST(MaterialFastPath, CollisionalCoefficientsAgainstTermByTermForm) {
  for (double zeta1 : {1.0, 0.0}) {
    const kt::Params P = collapse_c(zeta1);
    for (int i = 0; i <= 200; ++i) {
      const double V = P.Vmin + (P.Vcap - P.Vmin) * i / 200.0;
      const kt::Coefficients a = kt::coefficients(P, V), b = term_by_term(P, V);
      for (auto [x, y, what] : {std::tuple{a.g0, b.g0, "g0"}, {a.p_hat, b.p_hat, "p_hat"}, {a.eta_hat, b.eta_hat, "eta_hat"},
                                {a.gam_hat, b.gam_hat, "gam_hat"}, {a.diss_hat, b.diss_hat, "diss_hat"},
                                {a.div_hat, b.div_hat, "div_hat"}, {a.energy, b.energy, "energy"},
                                {a.p_star, b.p_star, "p_star"}, {a.zeta0, b.zeta0, "zeta0"}})
        EXPECT_NEAR(x, y, 1e-12 * (std::fabs(y) + 1e-300) + (std::string(what) == "div_hat" ? 1e-12 * b.p_hat : 0))
            << what << " at V = " << V << ", zeta1 = " << zeta1;
    }
    if (zeta1 == 0) EXPECT_EQ(kt::coefficients(P, 0.5).div_hat, 0.0);
  }
  const kt::Params P = collapse_c();
  const kt::Coefficients c = kt::coefficients(P, 0.3);
  EXPECT_NEAR(c.g0, 1.7 / (2 * 0.343), 1e-14);
  EXPECT_NEAR(c.p_star, 1 + 2 * (1 + P.eps) * 0.3 * 1.7 / (2 * 0.343), 1e-13);
  EXPECT_NEAR(c.p_hat, 2650 * 0.3 * c.p_star, 1e-10);
}

// The kernels skip loading and rotating the incoming stress for phaseTransition
// (reads_stress = false): its update must indeed not depend on it.
TEST(MaterialFastPath, PhaseTransitionIgnoresTheIncomingStress) {
  static_assert(!PhaseTransition::reads_stress);
  PhaseTransition::Params P{collapse_f(), collapse_c(), 0.95, 1e-12};
  Sym3 s0{{-3e3, -6e3, -3e3, 500, 0, 0}};
  PhaseTransition::State a = PhaseTransition::initial_state(P, s0), b = a;
  StrainIncrement inc{Sym3{{1e-5, -2e-5, 0, 3e-5, 0, 0}}, Spin3{2e-5, 0, 0}, 1e-5, 1};
  Sym3 sa = s0, sb{{1e9, -7, 3, 1e5, 0, 0}};
  PhaseTransition::update(P, a, sa, inc);
  PhaseTransition::update(P, b, sb, inc);
  for (int k = 0; k < 6; ++k) EXPECT_EQ(sa[k], sb[k]);
}
