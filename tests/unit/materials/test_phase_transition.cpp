// phaseTransition (Feng et al. 2025, eq. 1): frictional + collisional stresses in parallel.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "material_test_util.hpp"

using namespace scree;
using namespace scree::materials;
using namespace scree::materials::mtest;

namespace {

PhaseTransition::Params collapse_params(double e0) {
  return PhaseTransition::Params{table3_collapse_f(), table3_collapse_c(), e0, 1e-12};
}

struct SteadyPT {
  double tau_f, tau_col, qf, qcol, Kcol, T, pf;
};

/// Constant-volume simple shear at a constant rate up to gamma_end; the state at the end.
SteadyPT shear_at_rate(const PhaseTransition::Params& P, const Sym3& sig0, double gdot, double gamma_end,
                       double dgamma) {
  PointMaterialOf<PhaseTransition> m(P);
  Sym3 sig = sig0;
  m.initialise(sig);
  const long n = std::lround(gamma_end / dgamma);
  for (long i = 0; i < n; ++i) m.update(sig, shear_increment(dgamma, dgamma / gdot));
  const auto& s = m.raw_state();
  SteadyPT r{};
  r.tau_f = s.sigf[3];
  r.tau_col = sig[3] - s.sigf[3];
  r.qf = deviatoric_stress(s.sigf);
  r.qcol = deviatoric_stress(sig - s.sigf);
  r.Kcol = PhaseTransition::collisional_fraction(s, sig);
  r.T = s.T;
  r.pf = pressure(s.sigf);
  return r;
}

}  // namespace

// Fig. 7 / section 4.1.2: in the steady state of constant-volume shear the frictional part is
// at its (rate-independent) critical state while the collisional part grows as gdot^2
// (Bagnold), so K_col = q_col/(q_col + q_f) rises monotonically with the shear rate: at low
// rates the frictional part carries > 95 % of the shear stress, at high rates the collisional
// part dominates. Table 3 column-collapse parameters, e0 = 0.95 (p_cs = 12.8 kPa from eq. 16),
// from a K0 state (sigma_v = 10 kPa, K0 = 0.5; from an isotropic state the contraction at
// kappa ~ 0 liquefies this sample before it can dilate, see the README).
TEST(PhaseTransition, CollisionalFractionRisesWithShearRate) {
  const PhaseTransition::Params P = collapse_params(0.95);
  const Sym3 sig0 = k0_stress(10e3, 0.5);
  std::vector<double> rates = {0.1, 1, 10, 100, 1000, 1e4};
  std::vector<SteadyPT> st;
  for (double g : rates) st.push_back(shear_at_rate(P, sig0, g, 3.0, 1e-3));
  for (std::size_t i = 0; i < st.size(); ++i) {
    SCOPED_TRACE(rates[i]);
    EXPECT_NEAR(st[i].tau_f / st[0].tau_f, 1.0, 1e-3);  // frictional part rate independent
    EXPECT_NEAR(st[i].pf / st[0].pf, 1.0, 1e-3);
    EXPECT_NEAR(st[i].T / (rates[i] * rates[i]) / (st[0].T / (rates[0] * rates[0])), 1.0, 1e-2);  // T ~ gdot^2
    if (i > 0) {
      EXPECT_GT(st[i].Kcol, st[i - 1].Kcol);
    }
  }
  EXPECT_GT(st.front().tau_f / (st.front().tau_f + st.front().tau_col), 0.95);
  EXPECT_LT(st.front().Kcol, 0.05);
  EXPECT_GT(st.back().tau_col / (st.back().tau_f + st.back().tau_col), 0.5);
  EXPECT_GT(st.back().Kcol, 0.5);
  // the frictional steady state is the critical state of eq. (16) at e = e0
  const simsand::Params f = table3_collapse_f();
  EXPECT_NEAR(simsand::critical_void_ratio(f, st[0].pf) / 0.95, 1.0, 2e-3);
}

// The collisional part of phaseTransition is the kineticTheory material: sharing the void
// ratio, the same strain history gives the same T and sigma_col.
TEST(PhaseTransition, CollisionalPartEqualsKineticTheory) {
  const double e0 = 0.95;
  const PhaseTransition::Params P = collapse_params(e0);
  KineticTheory::Params K{table3_collapse_c(), e0, 1e-12};
  PointMaterialOf<PhaseTransition> pt(P);
  PointMaterialOf<KineticTheory> kt(K);
  Sym3 s1 = iso_stress(10e3), s2 = Sym3::zero();
  pt.initialise(s1);
  kt.initialise(s2);
  for (int i = 0; i < 2000; ++i) {
    const double gdot = 50 + 0.1 * i, dt = 1e-4;
    pt.update(s1, shear_increment(gdot * dt, dt));
    kt.update(s2, shear_increment(gdot * dt, dt));
  }
  EXPECT_NEAR(pt.raw_state().T / kt.raw_state().T, 1.0, 1e-12);
  const Sym3 col = s1 - pt.raw_state().sigf;
  for (int c = 0; c < 6; ++c) EXPECT_NEAR(col[c], s2[c], 1e-9 * norm(s2));
}

// Objectivity: a rigid rotation (spin increments only) of a stressed state leaves the
// invariants of the frictional stress unchanged (Hughes-Winget rotation is orthogonal); the
// collisional stress at D = 0 is isotropic (only p_col, decaying by dissipation).
TEST(PhaseTransition, RigidRotationKeepsInvariants) {
  const PhaseTransition::Params P = collapse_params(0.95);
  PointMaterialOf<PhaseTransition> m(P);
  Sym3 sig = k0_stress(10e3, 0.5);
  m.initialise(sig);
  for (int i = 0; i < 500; ++i) m.update(sig, shear_increment(1e-3, 1e-4));  // stressed, T > 0
  // a general 3D state: add some yz/zx shear
  StrainIncrement inc3;
  inc3.deps = Sym3{{-1e-4, 2e-4, -1e-4, 0, 3e-4, -2e-4}};
  inc3.spin = Spin3::zero();
  inc3.dt = 1e-4;
  inc3.J = 1;
  m.update(sig, inc3);
  const Sym3 sf0 = m.raw_state().sigf;
  const double p0 = pressure(sf0), q0 = deviatoric_stress(sf0), J30 = simsand::sym_det(deviator(sf0));
  ASSERT_GT(q0, 0.1 * p0);
  for (int i = 0; i < 400; ++i) {
    StrainIncrement inc;
    inc.deps = Sym3::zero();
    inc.spin = Spin3{0.01, -0.007, 0.004};
    inc.dt = 1e-4;
    inc.J = 1;
    m.update(sig, inc);
  }
  const Sym3 sf = m.raw_state().sigf;
  EXPECT_NEAR(pressure(sf) / p0, 1.0, 1e-12);
  EXPECT_NEAR(deviatoric_stress(sf) / q0, 1.0, 1e-12);
  EXPECT_NEAR(simsand::sym_det(deviator(sf)) / J30, 1.0, 1e-9);
  EXPECT_GT(norm(sf - sf0), 0.1 * q0);  // it did rotate
  EXPECT_LT(deviatoric_stress(sig - sf), 1e-12 * p0);  // sigma_col isotropic at D = 0
  EXPECT_NEAR(pressure(sig), pressure(sf) + pressure(sig - sf), 1e-9 * p0);
}

// Simsand alone: rotation keeps p and q of the (total) stress.
TEST(Simsand, RigidRotationKeepsInvariants) {
  Simsand::Params P{table1(), 2650, 0.85};
  PointMaterialOf<Simsand> m(P);
  Sym3 sig = k0_stress(100e3, 0.5);
  m.initialise(sig);
  for (int i = 0; i < 100; ++i) m.update(sig, shear_increment(1e-4, 1));
  const double p0 = pressure(sig), q0 = deviatoric_stress(sig);
  for (int i = 0; i < 300; ++i) {
    StrainIncrement inc;
    inc.deps = Sym3::zero();
    inc.spin = Spin3{0.02, 0.01, -0.005};
    inc.dt = 1;
    inc.J = 1;
    m.update(sig, inc);
  }
  EXPECT_NEAR(pressure(sig) / p0, 1.0, 1e-12);
  EXPECT_NEAR(deviatoric_stress(sig) / q0, 1.0, 1e-12);
}

// Initial state: the given stress is the total stress; sigma_f = sigma + p_col(T0) I.
TEST(PhaseTransition, InitialStateSplitsStress) {
  PhaseTransition::Params P = collapse_params(0.95);
  P.T0 = 1e-3;  // a visible collisional pressure
  Sym3 sig = k0_stress(5e3, 0.6);
  const Sym3 s0 = sig;
  const PhaseTransition::State st = PhaseTransition::initial_state(P, sig);
  for (int c = 0; c < 6; ++c) EXPECT_NEAR(sig[c], s0[c], 1e-9 * 5e3);
  const double pcol = pressure(sig - st.sigf);
  EXPECT_GT(pcol, 0.0);
  EXPECT_NEAR(deviatoric_stress(sig - st.sigf), 0.0, 1e-9);
  EXPECT_EQ(st.e, 0.95);
  EXPECT_EQ(st.T, 1e-3);
  EXPECT_NEAR(PhaseTransition::density(P), 2650 / 1.95, 1e-9);
}
