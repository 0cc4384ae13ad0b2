// Robustness of the granular materials under what an MPM throws at them: random strain
// increments (fuzz, fixed seed), large increments, free surfaces (p -> 0, tension) and
// states at the densest packing V_sd.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "material_test_util.hpp"
#include "scree/materials/simsand_recorded_updates.hpp"

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

// Stiff updates (simsand_model.hpp, integrate() step 5): eight updates recorded from the 1 mm
// column collapse that take the explicit substepping alone more than 300 substeps: three
// stretched points (e = 19-46, M_p nearly 0) and five grains at a tenth of a pascal
// (3G|de_d|/p ~ 3,000). Replayed, each must
// match the converged path (1,000 sub-increments at STOL = 1e-8, modified Euler throughout)
// within 1 Pa = 10 STOL s_e (the error the substepping accepts per substep, ten times) and
// within 1e-4 in kappa. The explicit scheme alone does not: it holds the stretched points at
// a pressure where the converged path falls to the apex.
TEST(Robustness, StiffUpdatesMatchConvergedPath) {
  struct Recorded {
    int substeps;  // what the explicit substepping alone takes for this update
    Sym3 sig;
    double e, kappa;
    Sym3 deps;
  };
  const Recorded rec[] = {
    {1448,
     {{-74.646564228520603, -74.632991302552483, -74.635196714282458, 0.0020152717435200054, 0, 0}},
     30.878511815601549, 10.667610402493079,
     {{-0.0015458995639904658, 0.00030375263531509682, 0, 0.00027594088399184903, 0, 0}}},
    {1422,
     {{-85.336718360153768, -85.31293319628584, -85.311451104846981, 0.022555546272188549, 0, 0}},
     19.16810412328185, 6.4264474604284452,
     {{-0.0012621590671802157, -6.9005706314294738e-05, 0, 0.0011424209350001018, 0, 0}}},
    {1325,
     {{-46.992047456702494, -46.990497486497176, -46.990197964944379, 0.0015808373240092301, 0, 0}},
     45.534494175928728, 6.1544494783687052,
     {{-0.00083350114864077574, -0.00013302070144406781, 0, 0.00071838024215061631, 0, 0}}},
    {1045,
     {{-0.086657780976775206, -0.050602862414894131, -0.07523354092698939, 0.011207470672417154, 0, 0}},
     1.0532667611847357, 6.7606105495379936,
     {{-0.00070827278704712487, 0.00064999922456418675, 0, 0.00068099310753476957, 0, 0}}},
    {1035,
     {{-0.095681055217613817, -0.059114635634915251, -0.078518395118406165, 0.016548586429918688, 0, 0}},
     1.0531471135020158, 6.7614776100451328,
     {{-0.00069853249898697205, 0.0006440957427947772, 0, 0.00067115895061682597, 0, 0}}},
    {1034,
     {{-0.076097492580072604, -0.058687616782054183, -0.055417504466128954, 0.019559677187893594, 0, 0}},
     1.0535212040127646, 6.7588866512242083,
     {{-0.00069783463813984504, 0.00063443042558918646, 0, 0.00067183712593001555, 0, 0}}},
    {841,
     {{-0.072406104638818414, -0.082195302087622518, -0.0758194680459678, 0.0245777623820807, 0, 0}},
     1.0491543480590346, 11.113749725516261,
     {{0.00017296571206047303, -0.00021463215962389548, 0, 0.00074702459680853683, 0, 0}}},
    {837,
     {{-0.06618904420286631, -0.07066451312575571, -0.066022642811818841, 0.022112837140974211, 0, 0}},
     1.0495371421156596, 11.110263162510115,
     {{0.00017941718781056879, -0.00021403925150100672, 0, 0.00075360854689664192, 0, 0}}},
  };
  // cases/columnCollapse: Table 3 with integrationTolerance 1e-3
  simsand::Params P = simsand::make_params({.K0 = 120, .nu = 0.2, .n = 0.5, .pat = 101300, .phic_deg = 19.8,
                                            .eref = 0.977, .lambda = 0.0596, .xi = 0.365, .Ad = 0.7, .kp = 0.0044,
                                            .np = 2.4, .nd = 2.9, .pmin = 1.0, .stol = 1e-3, .lode = true});
  simsand::Params R = P;
  R.stol = 1e-8;
  for (const Recorded& r : rec) {
    Sym3 a = r.sig, c = r.sig;
    simsand::Vars va{r.e, r.kappa, 0}, vc = va;
    simsand::integrate(P, a, va, r.deps);
    for (int i = 0; i < 1000; ++i) simsand::integrate<simsand::EulerThroughout>(R, c, vc, r.deps * 1e-3);
    EXPECT_LT(norm(a - c), 10 * P.stol * P.serr) << "recorded update of " << r.substeps << " substeps";
    EXPECT_NEAR(va.kappa, vc.kappa, 1e-4) << "recorded update of " << r.substeps << " substeps";
    EXPECT_NEAR(va.e, vc.e, 1e-11 * (1 + vc.e));  // 1 + e follows the volume: the same up to round-off
  }
}

// The returns stay out of what they cannot follow: denser than critical (dilatancy builds p
// along the path) or compression outweighing the plastic contraction. There integrate() gives
// the modified-Euler answer, bit for bit.
TEST(Robustness, StiffReturnsLeaveDenseAndCompressedPathsAlone) {
  simsand::Params P = simsand::make_params({.K0 = 120, .nu = 0.2, .n = 0.5, .pat = 101300, .phic_deg = 19.8,
                                            .eref = 0.977, .lambda = 0.0596, .xi = 0.365, .Ad = 0.7, .kp = 0.0044,
                                            .np = 2.4, .nd = 2.9, .pmin = 1.0, .stol = 1e-3, .lode = true});
  struct Case {
    double p, e, kappa, vol;  // vol: tr deps per unit of |dev deps|
  };
  for (const Case& k : {Case{1, 0.75, 0.05, 0.0}, Case{10, 0.85, 0.002, 0.0}, Case{10, 1.2, 0.002, -1.0},
                        Case{30, 1.2, 0.05, -1.0}}) {
    Sym3 s0 = Sym3{{-k.p + 0.3 * k.p, -k.p - 0.3 * k.p, -k.p, 0.2 * k.p, 0, 0}};
    bool projected;
    simsand::yield_and_project(P, s0, k.e, k.kappa, true, projected);
    const double G = P.rG * simsand::bulk_modulus(P, k.e, k.p);
    Sym3 d{{0.6, -0.6, 0, 0.5, 0, 0}};
    d = d * (500 * k.p / (3 * G) / norm(d));  // 3G|de_d|/p = 500: hundreds of substeps
    d[0] += 0.5 * k.vol * norm(d);
    d[1] += 0.5 * k.vol * norm(d);
    Sym3 a = s0, b = s0;
    simsand::Vars va{k.e, k.kappa, 0}, vb = va;
    simsand::integrate(P, a, va, d);
    simsand::integrate<simsand::EulerThroughout>(P, b, vb, d);
    for (int c = 0; c < 6; ++c) EXPECT_EQ(a[c], b[c]) << "p " << k.p << " e " << k.e;
    EXPECT_EQ(va.kappa, vb.kappa);
  }
}

// The bound on an update's work (maxSubsteps): the slow updates recorded from the 5 mm column
// at its shipped tolerance (utilities/scree-bench/simsand-slow-updates-5mm-column.txt: 2,271
// updates that took 25-92 substeps) replayed with the case's parameters. At the default bound
// none reaches it; at a bound of 8 every one does, and integrate() says so. The truth is the
// same path integrated to convergence (STOL 1e-6, a bound it never reaches): at the bound the stress
// stays within the error control's own absolute scale s_e = 1e-3 p_at of it (an error the
// control accepts as small at any tolerance), as the unbounded updates at 1e-2 do.
TEST(Robustness, BoundedUpdatesSayTheyReachedTheBoundAndStayNearTheConvergedPath) {
  std::ifstream in(std::string(SCREE_SOURCE_DIR) + "/utilities/scree-bench/simsand-slow-updates-5mm-column.txt");
  ASSERT_TRUE(in) << "the recorded updates";
  const std::vector<simsand::RecordedUpdate> ups = simsand::read_recorded_updates(in);
  ASSERT_GT(ups.size(), 2000u);
  simsand::Params shipped = table3_collapse_f();
  shipped.stol = 1e-2;
  simsand::Params capped = shipped;
  capped.nmax = 8;
  simsand::Params converged = shipped;
  converged.stol = 1e-6;
  converged.nmax = 100000;
  int bounded_shipped = 0, bounded_capped = 0, bounded_converged = 0;
  double worst_shipped = 0, worst_capped = 0;
  for (const simsand::RecordedUpdate& u : ups) {
    Sym3 a = u.sig, b = u.sig, c = u.sig;
    simsand::Vars va = u.v, vb = u.v, vc = u.v;
    bounded_shipped += simsand::integrate(shipped, a, va, u.deps);
    bounded_capped += simsand::integrate(capped, b, vb, u.deps);
    bounded_converged += simsand::integrate(converged, c, vc, u.deps);
    worst_shipped = std::max(worst_shipped, norm(a - c));
    worst_capped = std::max(worst_capped, norm(b - c));
    EXPECT_NEAR(vb.e, vc.e, 1e-11 * (1 + vc.e));  // 1 + e follows the volume, bound or not
  }
  EXPECT_EQ(bounded_shipped, 0);
  EXPECT_EQ(bounded_converged, 0) << "the reference must not be bounded itself";
  EXPECT_EQ(bounded_capped, static_cast<int>(ups.size()));
  EXPECT_LT(worst_shipped, shipped.serr) << "Pa";
  EXPECT_LT(worst_capped, shipped.serr) << "Pa";
}

// The update in turns (material.hpp: update_begin, update_turn, update_end), which the GPU's
// kernel of the deferred points runs a turn at a time, against update(), which the other
// kernels run whole: the same result to the bit, and the same report of the bound. Over the
// column's recorded slow updates (substep chains of 25-92 turns, rejections, apex crossings,
// stiff remainders), for both models, at the shipped bound and at a bound of 8 (every one
// reaches it), with a spin so that the co-rotation is in the path.
TEST(Robustness, UpdatesInTurnsGiveUpdateToTheBit) {
  std::ifstream in(std::string(SCREE_SOURCE_DIR) + "/utilities/scree-bench/simsand-slow-updates-5mm-column.txt");
  ASSERT_TRUE(in) << "the recorded updates";
  const std::vector<simsand::RecordedUpdate> ups = simsand::read_recorded_updates(in);
  ASSERT_GT(ups.size(), 2000u);
  auto same = [](const auto& a, const auto& b) { return std::memcmp(&a, &b, sizeof(a)) == 0; };
  for (int nmax : {1000, 8}) {
    simsand::Params f = table3_collapse_f();
    f.stol = 1e-2;
    f.nmax = nmax;
    const Simsand::Params ps{f, 2650, 0.85};
    const PhaseTransition::Params pt{f, table3_collapse_c(), 0.95, 1e-12};
    int differ = 0, bounded = 0, turns = 0;
    for (const simsand::RecordedUpdate& u : ups) {
      StrainIncrement inc;
      inc.deps = u.deps;
      inc.spin = Spin3{};
      inc.spin.xy = 1e-4;
      inc.dt = 1e-5;
      inc.J = 1;
      {
        Simsand::State s0{u.v.e, u.v.kappa, u.v.epsEq, 0};
        Simsand::State a = s0, b = s0;
        Sym3 sa = u.sig, sb = u.sig;
        const bool ra = Simsand::update(ps, a, sa, inc);
        const bool rb = update_in_turns<Simsand>(ps, b, sb, inc);
        differ += !(same(a, b) && same(sa, sb) && ra == rb);
        bounded += ra;
      }
      {
        PhaseTransition::State s0{u.sig, u.v.e, 1e-3, u.v.epsEq, u.v.kappa, 0, 0};
        PhaseTransition::State a = s0, b = s0;
        Sym3 sa = Sym3::zero(), sb = Sym3::zero();
        const bool ra = PhaseTransition::update(pt, a, sa, inc);
        const bool rb = update_in_turns<PhaseTransition>(pt, b, sb, inc);
        differ += !(same(a, b) && same(sa, sb) && ra == rb);
        PhaseTransition::Work w;
        if (PhaseTransition::update_begin(pt, s0, Sym3::zero(), inc, w))
          while (PhaseTransition::update_turn(pt, w)) ++turns;
      }
    }
    EXPECT_EQ(differ, 0) << "updates whose turns differ from update(), bound " << nmax;
    if (nmax == 8) EXPECT_EQ(bounded, static_cast<int>(ups.size()));
    EXPECT_GT(turns, 20 * static_cast<int>(ups.size()) / (nmax == 8 ? 2 : 1)) << "the updates must take many turns";
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
