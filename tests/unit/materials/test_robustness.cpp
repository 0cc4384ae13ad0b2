// Robustness of the granular materials under what an MPM throws at them: random strain
// increments (fuzz, fixed seed), large increments, free surfaces (p -> 0, tension) and
// states at the densest packing V_sd.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "material_test_util.hpp"

using namespace scree;
using namespace scree::materials;
using namespace scree::materials::mtest;

namespace {

/// A random increment: direction uniform on the 6 components (plus a volumetric bias),
/// magnitude log-uniform in [1e-9, 3e-2], spin up to the same size, dt log-uniform.
struct Fuzzer {
  std::mt19937_64 rng;
  explicit Fuzzer(unsigned seed) : rng(seed) {}
  double uni(double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); }
  StrainIncrement next() {
    StrainIncrement inc;
    Sym3 d;
    for (int i = 0; i < 6; ++i) d[i] = uni(-1, 1);
    const double vol = uni(-1, 1);
    for (int i = 0; i < 3; ++i) d[i] += vol;  // compression and extension bursts
    const double mag = std::pow(10.0, uni(-9, std::log10(3e-2)));
    inc.deps = d * (mag / norm(d));
    inc.spin = Spin3{uni(-1, 1) * mag, uni(-1, 1) * mag, uni(-1, 1) * mag};
    inc.dt = std::pow(10.0, uni(-7, -1));
    inc.J = 1;
    return inc;
  }
};

template <class M, class Check>
void fuzz(const typename M::Params& P, const Sym3& sig0, unsigned seed, int n, Check check) {
  PointMaterialOf<M> m(P);
  Sym3 sig = sig0;
  m.initialise(sig);
  Fuzzer fz(seed);
  for (int i = 0; i < n; ++i) {
    const StrainIncrement inc = fz.next();
    m.update(sig, inc);
    ASSERT_TRUE(finite(sig)) << "step " << i;
    check(m.raw_state(), sig, i);
    if (::testing::Test::HasFatalFailure()) return;
    const double c = m.wave_speed(sig, 1e-3);
    ASSERT_TRUE(std::isfinite(c) && c > 0) << "wave speed at step " << i;
  }
}

}  // namespace

// Fuzz: never NaN, never tension (p_f >= 0, the frictional stress inside the cone), T >= 0,
// e > 0, finite positive wave speed. 20000 increments per material and start state.
TEST(Robustness, FuzzSimsand) {
  for (double sv : {0.0, 50.0, 200e3}) {
    Simsand::Params P{table1(), 2650, 0.85};
    fuzz<Simsand>(P, k0_stress(sv, 0.5), 11, 20000, [&](const Simsand::State& s, const Sym3& sig, int i) {
      ASSERT_GE(pressure(sig), -1e-9 * (1 + sv)) << i;
      ASSERT_TRUE(std::isfinite(s.e) && s.e > 0) << i;
      ASSERT_TRUE(std::isfinite(s.kappa) && s.kappa >= 0) << i;
      ASSERT_LE(deviatoric_stress(sig), 3 * pressure(sig) + 1e-9 * (1 + sv)) << i;  // within M < 3
    });
  }
}

TEST(Robustness, FuzzKineticTheory) {
  KineticTheory::Params P{table2(), 0.8, 1e-12};
  fuzz<KineticTheory>(P, Sym3::zero(), 12, 20000, [](const KineticTheory::State& s, const Sym3&, int i) {
    ASSERT_TRUE(std::isfinite(s.T) && s.T >= 0) << i;
    ASSERT_TRUE(std::isfinite(s.e) && s.e > 0) << i;
  });
}

TEST(Robustness, FuzzPhaseTransition) {
  for (int set = 0; set < 2; ++set) {
    const PhaseTransition::Params P =
        set == 0 ? PhaseTransition::Params{table3_collapse_f(), table3_collapse_c(), 0.95, 1e-12}
                 : PhaseTransition::Params{table3_element_f(), collisional(1050, 1e-3, 1 / 1.92, 0.4, 0.7, 0.1), 0.99,
                                           1e-12};
    fuzz<PhaseTransition>(P, k0_stress(set == 0 ? 2e3 : 500, 0.5), 13 + set, 20000,
                          [](const PhaseTransition::State& s, const Sym3&, int i) {
                            ASSERT_GE(pressure(s.sigf), -1e-9 * (1 + norm(s.sigf))) << i;
                            ASSERT_TRUE(std::isfinite(s.T) && s.T >= 0) << i;
                            ASSERT_TRUE(std::isfinite(s.e) && s.e > 0) << i;
                            ASSERT_TRUE(finite(s.sigf)) << i;
                          });
  }
}

// One large increment gives the answer of many small ones (the same straight strain path at
// the same rate): the substepping controls the local error (tolerance 1e-4), so 1 % is a
// safe bound for a 2 % shear strain increment through the hardening phase.
TEST(Robustness, LargeIncrementEqualsManySmall) {
  const double dg = 0.02, rate = 10;
  {
    Simsand::Params P{table1(), 2650, 0.85};
    Sym3 a = k0_stress(100e3, 0.5), b = a;
    PointMaterialOf<Simsand> ma(P), mb(P);
    ma.initialise(a);
    mb.initialise(b);
    ma.update(a, shear_increment(dg, dg / rate));
    const int n = 2000;
    for (int i = 0; i < n; ++i) mb.update(b, shear_increment(dg / n, dg / rate / n));
    EXPECT_LT(norm(a - b) / norm(b), 1e-2);
    EXPECT_NEAR(ma.raw_state().kappa / mb.raw_state().kappa, 1.0, 1e-2);
  }
  {
    PhaseTransition::Params P{table3_collapse_f(), table3_collapse_c(), 0.95, 1e-12};
    Sym3 a = k0_stress(10e3, 0.5), b = a;
    PointMaterialOf<PhaseTransition> ma(P), mb(P);
    ma.initialise(a);
    mb.initialise(b);
    // bring both to a flowing state first (same history)
    for (int i = 0; i < 1000; ++i) {
      ma.update(a, shear_increment(1e-3, 1e-3 / rate));
      mb.update(b, shear_increment(1e-3, 1e-3 / rate));
    }
    ma.update(a, shear_increment(dg, dg / rate));
    const int n = 2000;
    for (int i = 0; i < n; ++i) mb.update(b, shear_increment(dg / n, dg / rate / n));
    EXPECT_LT(norm(a - b) / norm(b), 1e-2);
    EXPECT_NEAR(ma.raw_state().T / mb.raw_state().T, 1.0, 1e-2);
  }
}

// Free surface: a lightly stressed point under extension separates (stress-free, no
// tension, no NaN); shearing at the apex keeps it stress-free; compression rebuilds a
// stress inside the yield cone; the wave speed stays positive (p_min regularisation).
TEST(Robustness, FreeSurfaceTensionAndRecompression) {
  PhaseTransition::Params P{table3_collapse_f(), table3_collapse_c(), 0.95, 1e-12};
  PointMaterialOf<PhaseTransition> m(P);
  Sym3 sig = k0_stress(100, 0.5);
  m.initialise(sig);
  StrainIncrement ext;
  ext.deps = Sym3{{1e-3, 1e-3, 0, 2e-4, 0, 0}};
  ext.spin = Spin3::zero();
  ext.dt = 1e-5;
  ext.J = 1;
  m.update(sig, ext);
  for (int c = 0; c < 6; ++c) EXPECT_EQ(m.raw_state().sigf[c], 0.0);
  for (int i = 0; i < 100; ++i) m.update(sig, shear_increment(1e-4, 1e-5));
  EXPECT_LT(norm(m.raw_state().sigf), 1e-6);
  EXPECT_GT(m.wave_speed(sig, 1e-3), 1.0);
  StrainIncrement cmp;
  cmp.deps = Sym3{{-2e-4, -3e-4, 0, 1e-4, 0, 0}};
  cmp.spin = Spin3::zero();
  cmp.dt = 1e-5;
  cmp.J = 1;
  for (int i = 0; i < 20; ++i) m.update(sig, cmp);
  const Sym3 sf = m.raw_state().sigf;
  EXPECT_GT(pressure(sf), 1.0);
  const simsand::Params f = table3_collapse_f();
  EXPECT_LE(deviatoric_stress(sf), f.Mc * pressure(sf) * (1 + 1e-6));  // inside the cone (g <= 1)
}

// At and beyond the densest disordered packing V_sd the kinetic theory is regularised (g0
// capped): rapid shearing gives finite stresses and temperatures.
TEST(Robustness, DensestPackingRegularised) {
  const kt::Params c = table3_collapse_c();  // e_sd = 0.62
  for (double e0 : {0.63, 0.62, 0.60, 0.5}) {
    PhaseTransition::Params P{table3_collapse_f(), c, e0, 1e-12};
    PointMaterialOf<PhaseTransition> m(P);
    Sym3 sig = k0_stress(1e3, 0.5);
    m.initialise(sig);
    for (int i = 0; i < 200; ++i) m.update(sig, shear_increment(1e-2, 1e-5));  // 1000 1/s
    ASSERT_TRUE(finite(sig)) << e0;
    EXPECT_TRUE(std::isfinite(m.raw_state().T) && m.raw_state().T >= 0) << e0;
    const double c_h = m.wave_speed(sig, 1e-3);
    EXPECT_TRUE(std::isfinite(c_h) && c_h > 0);
  }
}

// wave_speed = elastic P-wave speed + granular sound speed + 2 (4/3 eta + gamma)/(rho h).
TEST(Robustness, WaveSpeedIncludesViscousLimit) {
  PhaseTransition::Params P{table3_collapse_f(), table3_collapse_c(), 0.95, 1e-12};
  PointMaterialOf<PhaseTransition> m(P);
  Sym3 sig = k0_stress(10e3, 0.5);
  m.initialise(sig);
  for (int i = 0; i < 300; ++i) m.update(sig, shear_increment(1e-2, 1e-5));
  const auto& s = m.raw_state();
  const kt::Coefficients k = kt::coefficients(P.c, kt::solid_fraction(P.c, s.e));
  const double mu = 4.0 / 3 * k.eta_hat * std::sqrt(s.T) + k.gam_hat * std::sqrt(s.T);
  const double rho = m.density();
  const double h1 = 1e-3, h2 = 1e-2;
  EXPECT_NEAR(m.wave_speed(sig, h1) - m.wave_speed(sig, h2), 2 * mu / rho * (1 / h1 - 1 / h2),
              1e-9 * m.wave_speed(sig, h1));
  const double K = simsand::bulk_modulus(P.f, s.e, pressure(s.sigf));
  EXPECT_GT(m.wave_speed(sig, 1e30), std::sqrt(K / rho));
}

// update_elastic (material.hpp), the GPU kernels' cheap first pass, must be update() itself
// wherever it accepts an increment -- the same numbers to the last bit, since both run the
// same code (simsand::elastic_trial) -- and must leave the state and stress untouched
// wherever it declines. Along a fuzzed path (the fuzz's increments, so elastic steps,
// plastic loading, separation and the apex all occur), both outcomes must occur often.
template <class M>
void expect_elastic_path_is_update(const typename M::Params& P, const Sym3& sig0, unsigned seed) {
  typename M::State s;
  Sym3 sig = sig0;
  s = M::initial_state(P, sig);
  Fuzzer fz(seed);
  int accepted = 0, declined = 0;
  for (int i = 0; i < 20000; ++i) {
    StrainIncrement inc = fz.next();
    if (i % 2) inc.deps = inc.deps * 1e-3;  // many small (elastic) increments too
    const Sym3 sig_rot = corotate(sig, inc.spin);
    typename M::State s_full = s, s_el = s;
    Sym3 sig_full = sig_rot, sig_el = sig_rot;
    M::update(P, s_full, sig_full, inc);
    const bool ok = M::update_elastic(P, s_el, sig_el, inc);
    const typename M::State& want = ok ? s_full : s;
    const Sym3& want_sig = ok ? sig_full : sig_rot;
    ASSERT_EQ(std::memcmp(&s_el, &want, sizeof s_el), 0) << "state, step " << i << (ok ? " (accepted)" : " (declined)");
    for (int c = 0; c < 6; ++c) ASSERT_EQ(sig_el[c], want_sig[c]) << "stress " << c << ", step " << i;
    (ok ? accepted : declined)++;
    s = s_full;
    sig = sig_full;
  }
  EXPECT_GT(accepted, 2000) << "declined " << declined;
  EXPECT_GT(declined, 2000) << "accepted " << accepted;
}

TEST(Robustness, ElasticPathIsUpdateSimsand) {
  expect_elastic_path_is_update<Simsand>(Simsand::Params{table1(), 2650, 0.85}, k0_stress(50e3, 0.5), 21);
}
TEST(Robustness, ElasticPathIsUpdatePhaseTransition) {
  expect_elastic_path_is_update<PhaseTransition>(
      PhaseTransition::Params{table3_collapse_f(), table3_collapse_c(), 0.95, 1e-12}, k0_stress(2e3, 0.5), 22);
}
