// Kinetic theory (Feng et al. 2025 eqs. 19-28, Appendices A-B): checks against results derived in
// the test from Garzo & Dufty (1999) in their own variables (number density n, mass m,
// temperature in energy units m T, the cooling rate zeta = zeta0* n m T/eta0), not from the
// model's code path.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "material_test_util.hpp"

using namespace scree;
using namespace scree::materials;
using namespace scree::materials::mtest;

namespace {

/// Test-side Garzo-Dufty (1999) dense-gas constants for a solid fraction phi.
struct GD {
  double m, n, chi, eta0_coef, eta_star, kappa_star, p_over_T, cool_coef;
  // eta = eta_star eta0_coef sqrt(T); p = p_over_T T; Gamma = cool_coef T^{3/2} (tr D = 0)
};
GD garzo_dufty(double rho_p, double sigma, double phi, double alpha, double Vsd, double Vm) {
  GD g{};
  g.m = rho_p * kPi * sigma * sigma * sigma / 6;  // grain mass
  g.n = phi / (kPi * sigma * sigma * sigma / 6);  // number density
  // radial distribution (eqs. 25-26): f = 1 - ((phi - Vm)/(Vsd - Vm))^2 above V_m
  const double cs = (2 - phi) / (2 * std::pow(1 - phi, 3));
  const double x = (phi - Vm) / (Vsd - Vm);
  const double f = phi < Vm ? 1.0 : 1 - x * x;
  g.chi = f * cs + (1 - f) * 2 / (Vsd - phi);
  const double a = alpha;
  const double c = 32 * (1 - a) * (1 - 2 * a * a) / (81 - 17 * a + 30 * a * a * (1 - a));
  const double zeta0 = 5.0 / 12 * g.chi * (1 - a * a) * (1 + 3 * c / 32);
  const double nu_eta = g.chi * (1 - 0.25 * (1 - a) * (1 - a)) * (1 - c / 64);
  const double etak = (1 - 0.4 * (1 + a) * (1 - 3 * a) * phi * g.chi) / (nu_eta - 0.5 * zeta0);
  g.kappa_star = 128 / (5 * kPi) * phi * phi * g.chi * (1 + a) * (1 - c / 32);
  g.eta_star = etak * (1 + 0.8 * phi * g.chi * (1 + a)) + 0.6 * g.kappa_star;
  // eta0 = 5/(16 sigma^2) sqrt(m T_E/pi), T_E = m T
  g.eta0_coef = 5 / (16 * sigma * sigma) * std::sqrt(g.m * g.m / kPi);
  g.p_over_T = g.n * g.m * (1 + 2 * (1 + a) * phi * g.chi);
  // Gamma = 3/2 n T_E zeta, zeta = zeta0* nu0, nu0 = n T_E/eta0
  g.cool_coef = 1.5 * g.n * g.m * zeta0 * g.n * g.m / g.eta0_coef;
  return g;
}

/// Steady simple shear with production = dissipation: eta gdot^2 = Gamma.
struct Steady {
  double T, tau, sv;
};
Steady steady_shear(const GD& g, double gdot) {
  const double A = g.eta_star * g.eta0_coef;  // eta = A sqrt(T)
  const double T = A * gdot * gdot / g.cool_coef;
  return Steady{T, A * std::sqrt(T) * gdot, g.p_over_T * T};
}

Sym3 run_shear(const kt::Params& c, double e0, double gdot, double t_end, double dt, double& T) {
  KineticTheory::Params P{c, e0, 1e-12};
  PointMaterialOf<KineticTheory> m(P);
  Sym3 sig = Sym3::zero();
  m.initialise(sig);
  const long n = std::lround(t_end / dt);
  for (long i = 0; i < n; ++i) m.update(sig, shear_increment(gdot * dt, dt));
  T = m.raw_state().T;
  return sig;
}

}  // namespace

// Collisional steady simple shear: production 2 eta |dev D|^2 = eta gdot^2 balances the
// dissipation Gamma ~ T^{3/2}, so T ~ (d gdot)^2 and both stresses ~ rho_p d^2 gdot^2 (Bagnold).
// The constants come from the test's Garzo-Dufty transcription; 1 % as the issue asks (the
// integrator is exact in the steady state, so the agreement is in fact ~1e-10).
TEST(KineticTheory, SteadySimpleShearBagnoldScaling) {
  std::vector<double> Tn, taun, svn;
  for (double rho_p : {1500.0, 2650.0})
    for (double d : {1e-3, 2.5e-3})
      for (double e0 : {0.80, 0.95})
        for (double gdot : {5.0, 50.0, 500.0}) {
          const kt::Params c = collisional(rho_p, d, 0.6, 0.4, 0.6, 0.2);
          const double alpha = 0.6 - 1.5 * 0.2 * std::exp(-0.6);  // eq. (24)
          const double phi = 1 / (1 + e0);
          const GD g = garzo_dufty(rho_p, d, phi, alpha, 0.6, 0.4);
          const Steady s = steady_shear(g, gdot);
          double T = 0;
          const Sym3 sig = run_shear(c, e0, gdot, 200 / gdot, 0.5 / gdot, T);
          SCOPED_TRACE(testing::Message() << rho_p << " " << d << " " << e0 << " " << gdot);
          EXPECT_NEAR(T / s.T, 1.0, 1e-2);
          EXPECT_NEAR(sig[3] / s.tau, 1.0, 1e-2);
          EXPECT_NEAR(-sig[1] / s.sv, 1.0, 1e-2);
          EXPECT_NEAR(sig[0], sig[1], 1e-9 * s.sv);  // isotropic normal stresses in the theory
          if (e0 == 0.80 && rho_p == 1500.0) {
            Tn.push_back(T / (d * d * gdot * gdot));
            taun.push_back(sig[3] / (rho_p * d * d * gdot * gdot));
            svn.push_back(-sig[1] / (rho_p * d * d * gdot * gdot));
          }
        }
  for (std::size_t i = 1; i < Tn.size(); ++i) {  // Bagnold: scaled values independent of d, gdot
    EXPECT_NEAR(Tn[i] / Tn[0], 1.0, 1e-2);
    EXPECT_NEAR(taun[i] / taun[0], 1.0, 1e-2);
    EXPECT_NEAR(svn[i] / svn[0], 1.0, 1e-2);
  }
}

// Homogeneous cooling (D = 0): dT/dt = -zeta T with zeta ~ sqrt(T) gives Haff's law
// T(t) = T0/(1 + t/t_H)^2, 1/t_H = zeta(T0)/2. The exact update must reproduce it for one
// step or many.
TEST(KineticTheory, HomogeneousCoolingHaffLaw) {
  const double e0 = 0.9, T0 = 0.1;
  const kt::Params c = table2();
  const double alpha = c.eps;
  const GD g = garzo_dufty(c.rho_p, c.d, 1 / (1 + e0), alpha, c.Vsd, c.Vm);
  const double zeta0 = g.cool_coef / (1.5 * g.n * g.m) * std::sqrt(T0);  // zeta at T0
  for (int nsteps : {1, 7, 1000}) {
    KineticTheory::Params P{c, e0, T0};
    PointMaterialOf<KineticTheory> m(P);
    Sym3 sig = Sym3::zero();
    m.initialise(sig);
    const double t_end = 0.05;
    StrainIncrement inc;
    inc.deps = Sym3::zero();
    inc.spin = Spin3::zero();
    inc.dt = t_end / nsteps;
    inc.J = 1;
    for (int i = 0; i < nsteps; ++i) m.update(sig, inc);
    const double T_haff = T0 / std::pow(1 + 0.5 * zeta0 * t_end, 2);
    EXPECT_NEAR(m.raw_state().T / T_haff, 1.0, 1e-9) << nsteps;
    EXPECT_NEAR(-sig[1] / (g.p_over_T * T_haff), 1.0, 1e-9);
  }
}

// Limits of the transport coefficients: a dilute elastic gas has the Chapman-Enskog viscosity
// eta0 = 5/(16 d^2) sqrt(m T/pi) and the ideal-gas pressure rho T; a moderately dense elastic
// gas the Enskog viscosity eta/eta0 = 1/chi + 3.2 phi + 12.18 phi^2 chi (Chapman & Cowling;
// GD99's first Sonine approximation gives 12.34 for the last coefficient: 2 % tolerance) and
// the Enskog bulk viscosity.
TEST(KineticTheory, DiluteAndEnskogElasticLimits) {
  const double rho_p = 2000, d = 1e-3;
  const double m = rho_p * kPi * d * d * d / 6;
  const kt::Params c = collisional(rho_p, d, 0.6, 0.4, 1.0, 0.0);  // eps_r -> 1 - 1e-9
  {
    const double V = 2e-3;
    const kt::Coefficients k = kt::coefficients(c, V);
    const double eta0 = 5 / (16 * d * d) * std::sqrt(m * m / kPi);
    EXPECT_NEAR(k.eta_hat / eta0, 1.0, 1e-2);
    EXPECT_NEAR(k.p_hat / (rho_p * V), 1.0, 1e-2);
    EXPECT_LT(k.diss_hat, 1e-6 * k.p_hat / d);  // elastic: no dissipation
  }
  {
    const double V = 0.3;
    const kt::Coefficients k = kt::coefficients(c, V);
    const double chi = (2 - V) / (2 * std::pow(1 - V, 3));
    const double eta0 = 5 / (16 * d * d) * std::sqrt(m * m / kPi);
    EXPECT_NEAR(k.eta_hat / eta0 / (1 / chi + 3.2 * V + 12.18 * V * V * chi), 1.0, 2e-2);
    // Enskog bulk viscosity (4/9) n^2 d^4 chi sqrt(pi m T_E), T_E = m T: this fixes the factor
    // phi^2 chi of gamma* (A5 as printed has phi chi, README KT-3)
    const double n = V / (kPi * d * d * d / 6);
    EXPECT_NEAR(k.gam_hat / (4.0 / 9 * n * n * std::pow(d, 4) * chi * m * std::sqrt(kPi)), 1.0, 1e-6);
  }
}

// Dispersed points (kt::dispersed): below V_min (minSolidFraction) a point is grains in free
// flight: no stress, no wave, and its granular temperature is carried unchanged (no stress,
// so no work). Just above V_min the theory applies: strong shear heats the point and it
// carries a viscous stress. And the reason for the default V_min = 1e-3: the mean free path
// d/(6 sqrt(2) V g0) is then above 100 grain diameters.
TEST(KineticTheory, DispersedPointsCarryNoStressAndNoProduction) {
  const kt::Params c = table2();
  ASSERT_EQ(c.Vmin, 1e-3);
  const double mfp = c.d / (6 * std::sqrt(2.0) * c.Vmin * kt::radial_distribution(c, c.Vmin));
  EXPECT_GT(mfp, 100 * c.d);
  const double T0 = 0.5, gdot = 200, dt = 1e-5;
  for (double V : {0.5e-3, 0.999e-3, 1.001e-3, 2e-3}) {
    const KineticTheory::Params P{c, 1 / V - 1, T0};
    PointMaterialOf<KineticTheory> m(P);
    Sym3 sig = Sym3::zero();
    m.initialise(sig);
    for (int i = 0; i < 100; ++i) m.update(sig, shear_increment(gdot * dt, dt));
    const auto& s = m.raw_state();
    const double rho = c.rho_p * V;
    const double speed = KineticTheory::wave_speed(P, s, sig, rho, 0.005);
    SCOPED_TRACE(testing::Message() << "V = " << V);
    if (V < c.Vmin) {
      for (int k = 0; k < 6; ++k) EXPECT_EQ(sig[k], 0.0);
      EXPECT_EQ(s.T, T0);
      EXPECT_EQ(speed, 0.0);
      EXPECT_NEAR(s.rate, gdot / std::sqrt(3.0), 1e-9 * gdot);  // the rate output still says what it does
    } else {
      EXPECT_GT(s.T, T0);                          // viscous heating
      EXPECT_GT(std::fabs(sig[3]), 1e-3 * rho * T0);  // a shear stress
      EXPECT_GT(speed, 0.0);
    }
  }
  // phaseTransition: its frictional part goes too (no contact network), and comes back
  // stress-free when the point is compacted above V_min again.
  const PhaseTransition::Params P{table3_collapse_f(), table3_collapse_c(), 1 / 0.5e-3 - 1, T0};
  PointMaterialOf<PhaseTransition> m(P);
  Sym3 sig = iso_stress(100);
  m.initialise(sig);
  m.update(sig, shear_increment(gdot * dt, dt));
  for (int k = 0; k < 6; ++k) {
    EXPECT_EQ(sig[k], 0.0);
    EXPECT_EQ(m.raw_state().sigf[k], 0.0);
  }
  EXPECT_EQ(m.raw_state().T, T0);
}

// The paper-literal readings (bulkViscosity printed, dissipation printed; README KT-2, KT-3):
// (A5) as printed writes G where Garzo & Dufty have V G, so gamma* is 1/V times the GD99 value
// (and eta*, through its 0.6 gamma* term, moves by 0.6 (1/V - 1) gamma*); (B8) as printed
// carries one factor V fewer, so Gamma is 1/V times. Nothing else moves.
TEST(KineticTheory, PaperLiteralReadingsScaleByOneOverV) {
  const kt::Params gd = table3_collapse_c();
  kt::Constants c = gd;
  c.a5_printed = 1;
  const kt::Params a5 = kt::make_params(c);
  c.a5_printed = 0;
  c.b8_printed = 1;
  const kt::Params b8 = kt::make_params(c);
  for (double V : {0.01, 0.2, 0.45, 0.6}) {
    SCOPED_TRACE(testing::Message() << "V = " << V);
    const kt::Coefficients g = kt::coefficients(gd, V), a = kt::coefficients(a5, V), b = kt::coefficients(b8, V);
    EXPECT_NEAR(a.gam_star, g.gam_star / V, 1e-12 * a.gam_star);
    EXPECT_NEAR(a.eta_star - g.eta_star, 0.6 * (a.gam_star - g.gam_star), 1e-12 * a.eta_star);
    EXPECT_EQ(a.diss_hat, g.diss_hat);
    EXPECT_NEAR(b.diss_hat, g.diss_hat / V, 1e-12 * b.diss_hat);
    EXPECT_EQ(b.gam_star, g.gam_star);
    EXPECT_EQ(b.eta_star, g.eta_star);
    EXPECT_EQ(a.p_hat, g.p_hat);
    EXPECT_EQ(b.p_hat, g.p_hat);
  }
  // Steady simple shear (tr D = 0): production eta_hat sqrt(T) gdot^2 balances diss_hat T^{3/2},
  // so T = eta_hat gdot^2 / diss_hat: the printed (A5) raises T by eta*'s ratio, the printed
  // (B8) lowers it by V.
  const double e0 = 0.8, V = 1 / (1 + e0), gdot = 50;
  double Tg = 0, Ta = 0, Tb = 0;
  run_shear(gd, e0, gdot, 200 / gdot, 0.5 / gdot, Tg);
  run_shear(a5, e0, gdot, 200 / gdot, 0.5 / gdot, Ta);
  run_shear(b8, e0, gdot, 200 / gdot, 0.5 / gdot, Tb);
  const kt::Coefficients g = kt::coefficients(gd, V), a = kt::coefficients(a5, V);
  EXPECT_NEAR(Ta / Tg, a.eta_star / g.eta_star, 1e-6);
  EXPECT_NEAR(Tb / Tg, V, 1e-6);
  std::printf("steady shear at e = 0.8, 50 1/s: T printed-(A5)/GD99 %.3f, printed-(B8)/GD99 %.3f\n", Ta / Tg, Tb / Tg);
}

// Eq. (24) (Chialvo & Sundaresan 2013) and the g0 regularisation at V -> V_sd.
TEST(KineticTheory, EffectiveRestitutionAndRadialDistribution) {
  EXPECT_NEAR(kt::effective_restitution(0.6, 0.2), 0.6 - 0.3 * std::exp(-0.6), 1e-15);
  EXPECT_NEAR(kt::effective_restitution(0.7, 0.1), 0.7 - 0.15 * std::exp(-0.3), 1e-15);
  EXPECT_EQ(kt::effective_restitution(0.1, 0.5), 0.0);  // clamped: a restitution is >= 0
  const kt::Params c = table2();                          // V_sd = 0.6, g0max 1000
  EXPECT_NEAR(c.Vcap, 0.6 - 0.002, 1e-12);
  // continuity at V_m, growth towards V_sd, finite and constant beyond the cap
  EXPECT_NEAR(kt::radial_distribution(c, 0.4 - 1e-12), kt::radial_distribution(c, 0.4 + 1e-12), 1e-9);
  double prev = 0;
  for (double e : {2.0, 1.0, 0.8, 0.7, 0.68, 0.667, 0.6667, 0.5, 0.2}) {
    const double V = kt::solid_fraction(c, e);
    const double g0 = kt::radial_distribution(c, V);
    EXPECT_TRUE(std::isfinite(g0));
    EXPECT_GE(g0, prev);
    EXPECT_LE(g0, 1001.0);
    prev = g0;
  }
}

// The sound speed's dg0/dV (eqs. 25-26 differentiated by hand) against a central difference
// of g0 itself, in both branches and up to the cap. Step 1e-6: truncation ~ g0''' dV^2/6 and
// round-off ~ 1e-16 g0/dV, both under 1e-7 of the slope here (g0 <= 1000, slopes >= 2).
TEST(KineticTheory, RadialDistributionSlopeIsItsDerivative) {
  const kt::Params c = table2();
  const double dV = 1e-6;
  for (double V : {0.05, 0.2, 0.35, 0.399, 0.401, 0.45, 0.5, 0.55, 0.59, 0.597}) {
    const double fd = (kt::radial_distribution(c, V + dV) - kt::radial_distribution(c, V - dV)) / (2 * dV);
    EXPECT_NEAR(kt::radial_distribution_slope(c, V), fd, 1e-6 * std::fabs(fd)) << "V = " << V;
  }
}

// The temperature update is unconditionally stable: any time step gives a finite,
// non-negative T, and a very large step lands on the steady state (production = dissipation).
TEST(KineticTheory, TemperatureStableForAnyTimeStep) {
  const kt::Params c = table2();
  const double e0 = 0.85, gdot = 20;
  const GD g = garzo_dufty(c.rho_p, c.d, 1 / (1 + e0), c.eps, c.Vsd, c.Vm);
  const Steady s = steady_shear(g, gdot);
  for (double dt : {1e-9, 1e-6, 1e-3, 1.0, 1e3, 1e9}) {
    for (double T0 : {0.0, 1e-15, s.T, 1e3 * s.T}) {
      KineticTheory::Params P{c, e0, T0};
      PointMaterialOf<KineticTheory> m(P);
      Sym3 sig = Sym3::zero();
      m.initialise(sig);
      m.update(sig, shear_increment(gdot * dt, dt));
      const double T = m.raw_state().T;
      ASSERT_TRUE(std::isfinite(T) && T >= 0) << dt << " " << T0;
      ASSERT_TRUE(finite(sig));
      if (dt >= 1.0) {
        EXPECT_NEAR(T / s.T, 1.0, 1e-8);
      }
      // monotone approach: T moves towards the steady state and never overshoots
      const double lo = std::min(T0, s.T), hi = std::max(T0, s.T);
      EXPECT_GE(T, lo * (1 - 1e-9));
      EXPECT_LE(T, hi * (1 + 1e-9));
    }
  }
}

// Eq. (27), tension positive (the paper is compression positive): the collisional work
// sigma_col : D is a non-negative production in isochoric shear, and compression heats the gas.
TEST(KineticTheory, CollisionalWorkSign) {
  const kt::Params c = table2();
  const kt::Coefficients k = kt::coefficients(c, 0.55);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < 100; ++i) {
    Sym3 D{{u(rng), u(rng), u(rng), u(rng), u(rng), u(rng)}};
    D = deviator(D);
    const Sym3 s = kt::collisional_stress(k, 0.01, D);
    EXPECT_GE(ddot(s, D), 0.0);
  }
  // compression with no shear heats the gas: T ends above the homogeneous-cooling value
  double T_end[2];
  for (int k = 0; k < 2; ++k) {
    KineticTheory::Params P{c, 0.85, 1e-4};
    PointMaterialOf<KineticTheory> m(P);
    Sym3 sig = Sym3::zero();
    m.initialise(sig);
    StrainIncrement inc;
    const double d = k == 0 ? 0.0 : -1e-4;
    inc.deps = Sym3{{d, d, d, 0, 0, 0}};
    inc.spin = Spin3::zero();
    inc.dt = 1e-4;
    inc.J = 1;
    m.update(sig, inc);
    T_end[k] = m.raw_state().T;
  }
  EXPECT_GT(T_end[1], T_end[0]);
}

// timeStepTemperature steady (kt::step_temperature): the temperature the time step assumes is
// the fixed point of the exact update at the last step's rates: many steps of one strain rate
// from a cold state converge to it (an independent route: iterating the update, not the
// formula), and while the rate holds the next step's T never exceeds it. With `current` it
// is T itself. The state: dense (V = 0.58, V_sd = 0.6) and cold (T = 1e-4), compressed at tr D = -4000 1/s
// with shear 300 1/s, steps of 1e-6 s: the flume's blow-up (cases/flume/README.md).
TEST(KineticTheory, StepTemperatureIsTheSteadyStateOfTheRates) {
  kt::Constants k = table2();
  k.steady_step = 1;
  const kt::Params c = kt::make_params(k);
  const double V = 0.58, dt = 1e-6, trD = -4000, gdot = 300;
  const kt::Coefficients co = kt::coefficients(c, V);  // V frozen: the update's own assumption
  Sym3 D{{trD / 2, trD / 2, 0, gdot / 2, 0, 0}};
  const kt::RateInvariants ri = kt::rate_invariants(D);
  const double rate = std::sqrt(2.0 / 3 * ri.dev2);
  double T = 1e-4;
  const double Tstep = kt::step_temperature(c, co, T, rate, ri.tr);
  EXPECT_GT(Tstep, 100 * T) << "compression at V = 0.58 must heat far above the cold state";
  for (int i = 0; i < 200000; ++i) {
    const double Tn = kt::update_temperature(co, T, ri, dt);
    ASSERT_LE(Tn, Tstep * (1 + 1e-9)) << "step " << i << ": the update overshot the step's temperature";
    T = Tn;
  }
  EXPECT_NEAR(T / Tstep, 1.0, 1e-6) << "the fixed point of the update";
  // From above the steady state the step temperature is T itself.
  EXPECT_EQ(kt::step_temperature(c, co, 10 * Tstep, rate, ri.tr), 10 * Tstep);
  // `current` (the default): T itself.
  const kt::Params cur = table2();
  EXPECT_EQ(kt::step_temperature(cur, co, 1e-4, rate, ri.tr), 1e-4);
}
