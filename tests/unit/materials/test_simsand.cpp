// SIMSAND-type frictional model (Feng et al. 2025, eqs. 12-18): element tests against physical
// statements that follow from the model's equations independently of the integrator.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "material_test_util.hpp"

using namespace scree;
using namespace scree::materials;
using namespace scree::materials::mtest;

namespace {

// ---- independent transcriptions of eqs. (16)-(18) (test side; std::atan/std::sin path) ----
double ec_indep(const simsand::Params& P, double p) { return P.eref * std::exp(-P.lambda * std::pow(p / P.pat, P.xi)); }
double M_of_phi(double phi) { return 6 * std::sin(phi) / (3 - std::sin(phi)); }
double phic(const simsand::Params& P) { return std::atan(P.tanphic); }
double Mp_indep(const simsand::Params& P, double e, double p) {  // eq. (17)
  return M_of_phi(std::atan(std::pow(ec_indep(P, p) / e, P.np) * std::tan(phic(P))));
}
double Mpt_indep(const simsand::Params& P, double e, double p) {  // eq. (18)
  return M_of_phi(std::atan(std::pow(e / ec_indep(P, p), P.nd) * std::tan(phic(P))));
}
/// p on the critical-state line for void ratio e: invert eq. (16).
double pcs_indep(const simsand::Params& P, double e) { return P.pat * std::pow(std::log(P.eref / e) / P.lambda, 1 / P.xi); }
/// Sheng's g at Lode angle 0 (pure shear, sin 3 theta = 0): (2c^4/(1+c^4))^(1/4).
double g0_lode(double phi) {
  const double c = (3 - std::sin(phi)) / (3 + std::sin(phi));
  return std::pow(2 * std::pow(c, 4) / (1 + std::pow(c, 4)), 0.25);
}

struct ShearHistory {
  std::vector<double> gamma, p, tau, q, e;
  double kappa_end = 0;
};

ShearHistory undrained_simple_shear(const simsand::Params& f, double e0, double sv, double K0, double gamma_end,
                                    double dgamma) {
  Simsand::Params P{f, 2650, e0};
  PointMaterialOf<Simsand> m(P);
  Sym3 sig = k0_stress(sv, K0);
  m.initialise(sig);
  ShearHistory h;
  const long n = std::lround(gamma_end / dgamma);
  for (long i = 0; i <= n; ++i) {
    h.gamma.push_back(i * dgamma);
    h.p.push_back(pressure(sig));
    h.q.push_back(deviatoric_stress(sig));
    h.tau.push_back(sig[3]);
    h.e.push_back(m.raw_state().e);
    if (i < n) m.update(sig, shear_increment(dgamma, 1e-3));
  }
  h.kappa_end = m.raw_state().kappa;
  return h;
}

}  // namespace

// Fig. 4: constant-volume simple shear of dense to medium samples ends on the critical-state
// line: e stays e0 (undrained), so p must reach p_cs(e0) from eq. (16), and the stress ratio the
// critical value. In simple shear the radial flow (eq. 15) makes the deviator parallel to the
// imposed pure shear at the critical state, so sin 3theta = 0 and q/p = M_c g(0) (Sheng).
// Tolerances: the approach is asymptotic (hyperbolic hardening, 1 - h(kappa) = k_p/(k_p+kappa)
// ~ 1e-3 at gamma = 2), so the state is required within 0.3 % of the critical state.
TEST(Simsand, UndrainedSimpleShearReachesCriticalState) {
  const simsand::Params f = table1();
  const double Mcs = f.Mc * g0_lode(phic(f));
  for (double e0 : {0.80, 0.85, 0.90}) {
    SCOPED_TRACE(e0);
    const ShearHistory h = undrained_simple_shear(f, e0, 400e3, 0.5, 2.0, 1e-4);
    const double p = h.p.back(), q = h.q.back(), e = h.e.back();
    EXPECT_NEAR(e, e0, 1e-12);                                  // constant volume
    EXPECT_NEAR(e / ec_indep(f, p), 1.0, 3e-3);                 // on the CSL (eq. 16)
    EXPECT_NEAR(p / pcs_indep(f, e0), 1.0, 3e-2);               // p_cs(e0); dlnp/dln(e) ~ 10 amplifies
    EXPECT_NEAR(q / p / Mcs, 1.0, 3e-3);                        // critical stress ratio, theta = 0
    // converged: the last 10 % of the shear changes the state by less than the tolerance
    const std::size_t k = h.p.size() * 9 / 10;
    EXPECT_LT(std::fabs(h.p.back() / h.p[k] - 1), 1e-2);
  }
}

// Fig. 4 behaviour: dense samples (e0 = 0.80, 0.85, e < e_c) tend to dilate, which at constant
// volume raises p and hardens; the medium sample (0.90, slightly loose at p0) first softens
// (p drops, contraction tendency) then hardens; the loose sample (0.95 > e_ref, looser than
// critical at every p) softens to static liquefaction.
TEST(Simsand, UndrainedSimpleShearDenseHardensLooseSoftens) {
  const simsand::Params f = table1();
  const double p0 = 400e3 * (1 + 2 * 0.5) / 3;
  for (double e0 : {0.80, 0.85}) {
    const ShearHistory h = undrained_simple_shear(f, e0, 400e3, 0.5, 0.5, 1e-4);
    EXPECT_GT(h.p.back(), 2 * p0) << e0;
    EXPECT_GT(h.tau.back(), *std::max_element(h.tau.begin(), h.tau.begin() + h.tau.size() / 10)) << e0;
  }
  {
    const ShearHistory h = undrained_simple_shear(f, 0.90, 400e3, 0.5, 0.5, 1e-4);
    const double pmin = *std::min_element(h.p.begin(), h.p.end());
    EXPECT_LT(pmin, 0.5 * p0);
    EXPECT_GT(h.p.back(), 2 * pmin);
  }
  {
    const ShearHistory h = undrained_simple_shear(f, 0.95, 400e3, 0.5, 0.5, 1e-4);
    const double tau_peak = *std::max_element(h.tau.begin(), h.tau.end());
    EXPECT_GT(tau_peak, 0.0);
    EXPECT_LT(h.tau.back(), 1e-3 * tau_peak);  // softening to zero strength
    EXPECT_LT(h.p.back(), 1e-3 * p0);          // static liquefaction, p_f -> 0 (not negative)
    EXPECT_GE(h.p.back(), 0.0);
    // e0 > e_ref: the critical-state line e_c(p) <= e_ref cannot be reached (README)
    EXPECT_GT(h.e.back() / ec_indep(f, std::max(h.p.back(), 0.0)), 1.0);
  }
}

namespace {

/// Drained triaxial compression at constant mean stress p0 (axial y compressed, lateral x = z
/// free): the lateral strain increment is found by Newton iterations (secant) on p = p0,
/// restarting the material from a copy of its state.
struct TriaxialHistory {
  std::vector<double> ea, ev, eta, e, p, kappa;
};
TriaxialHistory drained_triaxial_constant_p(const simsand::Params& f, double e0, double p0, double ea_end,
                                            double dea) {
  Simsand::Params P{f, 2650, e0};
  Sym3 sig = iso_stress(p0);
  Simsand::State st = Simsand::initial_state(P, sig);
  TriaxialHistory h;
  double ea = 0, ev = 0, dl_prev = dea / 2;
  auto trial = [&](double dl, Sym3& s, Simsand::State& x) {
    s = sig;
    x = st;
    StrainIncrement inc;
    inc.deps = Sym3{{dl, -dea, dl, 0, 0, 0}};
    inc.spin = Spin3::zero();
    inc.dt = 1;
    inc.J = 1;
    Simsand::update(P, x, s, inc);
    return pressure(s) - p0;
  };
  const long n = std::lround(ea_end / dea);
  for (long i = 0; i <= n; ++i) {
    h.ea.push_back(ea);
    h.ev.push_back(ev);
    h.eta.push_back(deviatoric_stress(sig) / pressure(sig));
    h.e.push_back(st.e);
    h.p.push_back(pressure(sig));
    h.kappa.push_back(st.kappa);
    if (i == n) break;
    Sym3 s1, s2;
    Simsand::State x1, x2;
    double a = dl_prev, b = dl_prev * 1.01 + 1e-9;
    double ra = trial(a, s1, x1), rb = trial(b, s2, x2);
    for (int it = 0; it < 30 && std::fabs(rb) > 1e-9 * p0; ++it) {
      const double c = b - rb * (b - a) / (rb - ra);
      a = b;
      ra = rb;
      b = c;
      rb = trial(b, s2, x2);
    }
    sig = s2;
    st = x2;
    dl_prev = b;
    ea += dea;
    ev += dea - 2 * b;  // compression positive
  }
  return h;
}

}  // namespace

// Drained triaxial compression at constant p (Lode angle of compression, g = 1):
//  - at constant p the elastic volumetric strain is zero, so the volumetric response is the
//    plastic one, dilatancy d = A_d (M_pt - q/p) (eq. 15): it turns from contraction to
//    dilation exactly where q/p = M_pt(e, p) (eq. 18);
//  - the peak stress ratio is the peak ratio M_p(e, p) of eq. (17) times the hyperbolic factor
//    kappa/(k_p + kappa) of eq. (14): kappa ~ 0.028 at the peak here, so the peak is within
//    4 % below M_p (and on the yield surface to 1e-3);
//  - at large strain the sample reaches the critical state: e -> e_c(p0), q/p -> M_c.
TEST(Simsand, DrainedTriaxialConstantPDense) {
  const simsand::Params f = table1();
  const double p0 = 200e3, e0 = 0.80;
  const TriaxialHistory h = drained_triaxial_constant_p(f, e0, p0, 0.6, 2e-4);
  // pressure held
  for (double p : h.p) ASSERT_NEAR(p / p0, 1.0, 1e-8);
  // contraction -> dilation at M_pt
  std::size_t k = 0;
  for (std::size_t i = 2; i < h.ev.size(); ++i) {
    if (h.ev[i] - h.ev[i - 1] < 0 && h.ev[i - 1] - h.ev[i - 2] >= 0) {
      k = i - 1;
      break;
    }
  }
  ASSERT_GT(k, 0u) << "no transition from contraction to dilation";
  EXPECT_NEAR(h.eta[k] / Mpt_indep(f, h.e[k], p0), 1.0, 1e-2);
  // peak stress ratio
  const std::size_t ip = std::max_element(h.eta.begin(), h.eta.end()) - h.eta.begin();
  ASSERT_GT(ip, k) << "the peak comes after the phase transformation";
  ASSERT_LT(ip + 10, h.eta.size()) << "a peak, then softening";
  const double Mp = Mp_indep(f, h.e[ip], p0);
  EXPECT_NEAR(h.eta[ip] / Mp, 1.0, 4e-2);
  EXPECT_LE(h.eta[ip], Mp * (1 + 1e-6));
  EXPECT_NEAR(h.eta[ip], Mp * h.kappa[ip] / (f.kp + h.kappa[ip]), 1e-3 * Mp);  // on the surface (eq. 14)
  EXPECT_GT(Mp, f.Mc);  // dense: M_p > M_c
  // critical state at large strain
  EXPECT_NEAR(h.e.back() / ec_indep(f, p0), 1.0, 5e-3);
  EXPECT_NEAR(h.eta.back() / f.Mc, 1.0, 1e-2);
}

// A loose sample (e0 > e_c(p0)): M_pt > M_c while e > e_c (eq. 18), so it contracts (with A_d = 4
// it overshoots the critical void ratio slightly and then dilates back); the stress ratio
// hardens monotonically without a peak above M_c, wherever the volumetric response turns the
// stress ratio is M_pt, and the sample ends at the critical state.
TEST(Simsand, DrainedTriaxialConstantPLoose) {
  const simsand::Params f = table1();
  const double p0 = 200e3, e0 = 0.93;
  ASSERT_GT(e0, ec_indep(f, p0));
  const TriaxialHistory h = drained_triaxial_constant_p(f, e0, p0, 0.6, 2e-4);
  for (std::size_t i = 1; i < h.eta.size(); ++i) ASSERT_GE(h.eta[i], h.eta[i - 1] - 1e-9) << "softening at " << i;
  EXPECT_LT(*std::max_element(h.eta.begin(), h.eta.end()), f.Mc * (1 + 1e-6));
  // net contraction to the critical void ratio: eps_v = ln((1 + e0)/(1 + e_c))
  EXPECT_NEAR(h.ev.back(), std::log((1 + e0) / (1 + ec_indep(f, p0))), 1e-3);
  int turns = 0;
  for (std::size_t i = 2; i < h.ev.size(); ++i) {
    const double d1 = h.ev[i - 1] - h.ev[i - 2], d2 = h.ev[i] - h.ev[i - 1];
    if (d1 > 0 && d2 <= 0) {
      ++turns;
      EXPECT_NEAR(h.eta[i - 1] / Mpt_indep(f, h.e[i - 1], p0), 1.0, 1e-3);
    }
  }
  EXPECT_LE(turns, 1);
  EXPECT_NEAR(h.e.back() / ec_indep(f, p0), 1.0, 5e-3);
  EXPECT_NEAR(h.eta.back() / f.Mc, 1.0, 1e-2);
}

// Isotropic compression is elastic (q = 0 stays on the apex line of the cone) and the
// nonlinear stiffness eq. (13) is integrated consistently: with e = (1+e0) exp(-eps_v) - 1,
//   integral (p + p_min)^(-n) dp = K0 p_at^(1-n) integral F(e(eps_v)) d eps_v,
// evaluated here by Simpson's rule. One large increment and many small ones both match.
TEST(Simsand, IsotropicCompressionFollowsNonlinearElasticity) {
  const simsand::Params f = table1();
  const double e0 = 0.85, p0 = 50e3, ev_end = 0.01;
  auto F = [](double e) { return (2.97 - e) * (2.97 - e) / (1 + e); };
  const int ns = 2000;  // Simpson
  double I = 0;
  for (int i = 0; i <= ns; ++i) {
    const double ev = ev_end * i / ns;
    const double w = (i == 0 || i == ns) ? 1 : (i % 2 ? 4 : 2);
    I += w * F((1 + e0) * std::exp(-ev) - 1);
  }
  I *= ev_end / ns / 3;
  const double m = 1 - f.n;
  const double p_exact =
      std::pow(std::pow(p0 + f.pmin, m) + m * f.K0 * std::pow(f.pat, m) * I, 1 / m) - f.pmin;
  for (int nsteps : {1, 10, 1000}) {
    Simsand::Params P{f, 2650, e0};
    Sym3 sig = iso_stress(p0);
    Simsand::State st = Simsand::initial_state(P, sig);
    for (int i = 0; i < nsteps; ++i) {
      StrainIncrement inc;
      const double d = -ev_end / 3 / nsteps;
      inc.deps = Sym3{{d, d, d, 0, 0, 0}};
      inc.spin = Spin3::zero();
      inc.dt = 1;
      inc.J = 1;
      Simsand::update(P, st, sig, inc);
    }
    // frozen-e secant integration: error O(de) per increment relative to the e-dependence of F
    const double tol = nsteps == 1 ? 2e-3 : 2e-5;
    EXPECT_NEAR(pressure(sig) / p_exact, 1.0, tol) << nsteps;
    EXPECT_NEAR(deviatoric_stress(sig), 0.0, 1e-9 * p0);
    EXPECT_EQ(st.kappa, 0.0);
  }
}

// Initial K0 stress states are put on (inside) the yield surface: kappa such that
// M_p kappa/(k_p + kappa) = q/p; the stress is not changed.
TEST(Simsand, InitialStateOnYieldSurface) {
  const simsand::Params f = table1();
  Simsand::Params P{f, 2650, 0.85};
  Sym3 sig = k0_stress(100e3, 0.5);
  const Sym3 s0 = sig;
  const Simsand::State st = Simsand::initial_state(P, sig);
  for (int i = 0; i < 6; ++i) EXPECT_EQ(sig[i], s0[i]);
  const double eta = deviatoric_stress(sig) / pressure(sig);  // triaxial compression: g = 1
  EXPECT_NEAR(Mp_indep(f, 0.85, pressure(sig)) * st.kappa / (f.kp + st.kappa), eta, 1e-12);
  // tension is cut
  Sym3 t{{1e3, 2e3, 5e2, 0, 0, 0}};
  Simsand::initial_state(P, t);
  for (int i = 0; i < 6; ++i) EXPECT_EQ(t[i], 0.0);
}

// The GPU kernels' elastic path (simsand::integrate_elastic) skips integrate()'s start check:
// it takes the start stress as admissible, as every state the integrator leaves is. From a
// start outside the surface by f0 whose isotropic compression unloads it, integrate() first
// scales the deviator back onto the surface, q0 -> q0 - f0 p0 g, and the elastic path does
// not; an isotropic increment leaves the deviator alone, so the two results differ by exactly
// that in q (g = 1 in triaxial compression), share p and e, and both end admissible.
TEST(Simsand, ElasticPathFromOutsideDiffersByTheStartProjection) {
  const simsand::Params f = table1();
  Simsand::Params P{f, 2650, 0.85};
  Sym3 sig0 = k0_stress(100e3, 0.5);
  const Simsand::State st = Simsand::initial_state(P, sig0);
  simsand::Vars v0{st.e, 0.99 * st.kappa, 0};  // hardening 1% back: the start lies outside
  const double f0 = simsand::yield(P.m, sig0, v0.e, v0.kappa);
  ASSERT_GT(f0, 1e-6);
  const double p0 = pressure(sig0);
  Sym3 deps = Sym3::zero();
  for (int i = 0; i < 3; ++i) deps[i] = -2e-4;  // isotropic compression: q/p falls
  Sym3 s_el = sig0, s_full = sig0;
  simsand::Vars v_el = v0, v_full = v0;
  ASSERT_TRUE(simsand::integrate_elastic(P.m, s_el, v_el, deps));
  simsand::integrate(P.m, s_full, v_full, deps);
  EXPECT_EQ(v_el.e, v_full.e);
  EXPECT_EQ(v_el.kappa, v_full.kappa);
  EXPECT_NEAR(pressure(s_el), pressure(s_full), 1e-12 * p0);
  EXPECT_NEAR(deviatoric_stress(s_el) - deviatoric_stress(s_full), f0 * p0, 1e-9 * deviatoric_stress(s_el));
  EXPECT_LE(simsand::yield(P.m, s_el, v_el.e, v_el.kappa), simsand::kFtol);
  EXPECT_LE(simsand::yield(P.m, s_full, v_full.e, v_full.kappa), simsand::kFtol);
}

// Dispersed points (minSolidFraction V_min): below a solid fraction of 1e-3 a point's grains
// are out of contact (the mean spacing of grains at V = 1e-3 is about 8 diameters), so it
// carries no frictional stress and sets no wave speed; just above it the model applies.
// Without this a point stretched to J = 6.9e5 in the flume's frictional run at 5 mm kept
// eq. (13)'s stiffness at p_min with a density of 0.0019 kg/m^3: c = 3,000 m/s, dt 7e-7 s.
TEST(Simsand, DispersedPointsCarryNoStressAndNoWave) {
  const double Vmin = 1e-3, rho_p = 2650;
  for (double V : {0.5e-3, 0.999e-3, 1.001e-3, 2e-3}) {
    const Simsand::Params P{table3_collapse_f(), rho_p, 1 / V - 1, Vmin};
    PointMaterialOf<Simsand> m(P);
    Sym3 sig = iso_stress(100);
    m.initialise(sig);
    for (int i = 0; i < 10; ++i) m.update(sig, shear_increment(1e-4, 1e-5));
    const double speed = Simsand::wave_speed(P, m.raw_state(), sig, rho_p * V, 0.005);
    SCOPED_TRACE(testing::Message() << "V = " << V);
    if (V < Vmin) {
      for (int k = 0; k < 6; ++k) EXPECT_EQ(sig[k], 0.0);
      EXPECT_EQ(speed, 0.0);
    } else {
      EXPECT_GT(pressure(sig), 0.0);           // the contact network carries the pressure
      EXPECT_GT(std::fabs(sig[3]), 0.0);       // and a shear stress
      EXPECT_GT(speed, 0.0);
    }
  }
  // Compacted above V_min again, the point comes back stress-free and stiffens from there.
  const Simsand::Params P{table3_collapse_f(), rho_p, 1 / 0.9e-3 - 1, Vmin};
  PointMaterialOf<Simsand> m(P);
  Sym3 sig = Sym3::zero();
  m.initialise(sig);
  StrainIncrement squeeze = shear_increment(0, 1e-5);
  squeeze.deps[0] = squeeze.deps[1] = -0.05;  // volume x 0.905 per step (1 + e follows exp(tr deps))
  for (int i = 0; i < 3; ++i) m.update(sig, squeeze);
  EXPECT_GT(1 / (1 + m.raw_state().e), Vmin);
  EXPECT_GT(pressure(sig), 0.0);
  // The default of the dictionary keyword.
  EXPECT_EQ(std::stod(*Simsand::spec().find("minSolidFraction")->default_text()), 1e-3);
}
