// The materials in 3D: paths whose stress is not plane strain, with answers known independently
// of the code.
//
//  * SIMSAND's critical state in 3D (Feng et al. 2025 eqs. 14-16 with Sheng, Sloan & Yu's (2000)
//    Lode dependence, materials/simsand/README.md): at the critical state the stress ratio is
//    q/p = M_c g(theta), g(theta) = [2c^4/(1 + c^4 - (1 - c^4) sin 3theta)]^{1/4},
//    c = (3 - sin phi_c)/(3 + sin phi_c). So
//      triaxial compression (sin 3theta = +1): q/p = M_c = 6 sin phi_c/(3 - sin phi_c),
//      triaxial extension   (sin 3theta = -1): q/p = M_e = c M_c = 6 sin phi_c/(3 + sin phi_c)
//        (the Mohr-Coulomb ratio M_e/M_c = (3 - sin phi_c)/(3 + sin phi_c)),
//      a true-triaxial state at fixed b = (sigma_2 - sigma_3)/(sigma_1 - sigma_3): sin 3theta
//        is a function of b alone (below), and q/p = M_c g(theta(b)).
//    Driven through the element-test driver (utilities/scree-element/element_driver.hpp) with
//    mixed control: drainedTriaxial at constant cell pressure (conventional triaxial
//    compression) and drainedTrueTriaxial at constant p and b.
//  * Isotropy of the updates: a plane-strain history turned into an arbitrary plane of 3D space
//    (L' = R L R^T, sigma_0' = R sigma_0 R^T, every stress component non-zero) gives the turned
//    2D answer, R sigma R^T with the same internal state: the kinetic theory's simple shear in any
//    plane equals its 2D steady shear (its stress depends on D and T only through the
//    invariants), and SIMSAND's and phaseTransition's frictional histories to the critical state
//    agree likewise.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

#include "element_driver.hpp"
#include "material_test_util.hpp"

using namespace scree;
using namespace scree::materials;
using namespace scree::materials::mtest;
using namespace scree::element;

namespace {

// ---------------------------------------------------------------- independent transcriptions

double sin_phi(const simsand::Params& P) { return std::sin(std::atan(P.tanphic)); }
double Mc_of(const simsand::Params& P) { return 6 * sin_phi(P) / (3 - sin_phi(P)); }
/// Sheng, Sloan & Yu (2000): g(theta) from sin 3theta (+1 compression, -1 extension).
double sheng_g(const simsand::Params& P, double S) {
  const double c = (3 - sin_phi(P)) / (3 + sin_phi(P)), c4 = std::pow(c, 4);
  return std::pow(2 * c4 / (1 + c4 - (1 - c4) * S), 0.25);
}
/// sin 3theta of principal stresses (compression positive) with sigma_1 - sigma_3 = 1 and
/// sigma_2 - sigma_3 = b: deviators s_1 = (2 - b)/3, s_2 = (2b - 1)/3, s_3 = -(1 + b)/3;
/// sin 3theta = (3 sqrt3/2) s_1 s_2 s_3 / J2^{3/2}, J2 = (s_1^2 + s_2^2 + s_3^2)/2.
double sin3theta_of_b(double b) {
  const double s1 = (2 - b) / 3, s2 = (2 * b - 1) / 3, s3 = -(1 + b) / 3;
  const double J2 = 0.5 * (s1 * s1 + s2 * s2 + s3 * s3);
  return 1.5 * std::sqrt(3.0) * s1 * s2 * s3 / std::pow(J2, 1.5);
}
double ec_indep(const simsand::Params& P, double p) { return P.eref * std::exp(-P.lambda * std::pow(p / P.pat, P.xi)); }

struct TriaxialEnd {
  double eta, S, p, e, b, max_residual;
  long newton_failures;
};

/// Drained triaxial of simsand from an isotropic p0 to axial strain ea_end.
TriaxialEnd triaxial(const simsand::Params& f, double e0, double p0, Loading loading, double b, double ea_end,
                     double dea) {
  ElementPointOf<Simsand> m(Simsand::Params{f, 2650, e0});
  Program P;
  P.loading = loading;
  P.control = TriaxialControl::constantCellPressure;
  P.b = b;
  P.sigma0 = iso_stress(p0);
  P.segments = {Segment{ea_end, 1, true, 0}};
  P.dt = dea;
  P.output_interval = ea_end;
  const Result r = run(m, P);
  const Sym3 s = r.rows.back().sigma;
  const double sa = -s[1], sz = -s[2], sx = -s[0];  // compression positive
  const double big = std::max({sa, sz, sx}), small = std::min({sa, sz, sx});
  return TriaxialEnd{deviatoric_stress(s) / pressure(s), lode_sin3theta(s), pressure(s), r.rows.back().void_ratio,
                     (sz - sx) / (big - small), r.max_residual, r.newton_failures};
}

}  // namespace

// Conventional triaxial compression (constant cell pressure sigma_xx = sigma_zz = 200 kPa, axial
// y compressed) of a dense sample (e0 = 0.80 < e_c) to 60 % axial strain: a 3D axisymmetric
// state (sin 3theta = +1 exactly: sigma_xx = sigma_zz held by the Newton iterations), at the end
// on the critical state, q/p = M_c = 6 sin phi_c/(3 - sin phi_c) = 1.2 (phi_c = 30 deg) and
// e = e_c(p) (eq. 16). Tolerance 0.5 % on q/p and e/e_c: the approach to the critical state is
// asymptotic (the hardening 1 - kappa/(k_p + kappa) ~ 2e-3 at kappa ~ 0.5, and the dilatancy of
// eq. 15 decays with e - e_c), so at 60 % axial strain the state is within a few 1e-4 of it
// (measured: q/p 0.07 % below M_c, e 0.1 % below e_c; printed), while a wrong Lode dependence
// misses by 10-30 % (M_e/M_c = 0.714).
TEST(Simsand3D, ConventionalTriaxialCompressionReachesMc) {
  const simsand::Params f = table1();
  const TriaxialEnd t = triaxial(f, 0.80, 200e3, Loading::drainedTriaxial, 0, 0.6, 2e-4);
  EXPECT_EQ(t.newton_failures, 0);
  EXPECT_NEAR(t.S, 1.0, 1e-9) << "axisymmetric compression: sin 3theta = +1";
  EXPECT_NEAR(t.eta / Mc_of(f), 1.0, 5e-3);
  EXPECT_NEAR(t.e / ec_indep(f, t.p), 1.0, 5e-3);
  // constant cell pressure: p = sigma_c + q/3, so p/sigma_c = 1/(1 - eta/3)
  EXPECT_NEAR(t.p / 200e3, 1 / (1 - t.eta / 3), 1e-8);
  std::printf("CTC: q/p = %.5f (M_c %.5f), sin3theta %.9f, p %.1f Pa, e/e_c %.5f\n", t.eta, Mc_of(f), t.S, t.p,
              t.e / ec_indep(f, t.p));
}

// Triaxial extension at constant p (b = 1: sigma_1 = sigma_2 > sigma_3), to the critical state:
// q/p = M_e = c M_c = 6 sin phi_c/(3 + sin phi_c) = 0.857 for phi_c = 30 deg (Sheng's g = c at
// sin 3theta = -1, the Mohr-Coulomb extension vertex). With lodeDependence none (g = 1) the
// same path must end at M_c instead: the check can tell the two apart (0.857 vs 1.2).
TEST(Simsand3D, TriaxialExtensionReachesTheLodeDependentRatio) {
  const simsand::Params f = table1();
  const double s = sin_phi(f), Me = 6 * s / (3 - s) * (3 - s) / (3 + s);
  EXPECT_NEAR(Me, 6 * s / (3 + s), 1e-15);
  const TriaxialEnd t = triaxial(f, 0.80, 200e3, Loading::drainedTrueTriaxial, 1.0, 0.6, 2e-4);
  EXPECT_EQ(t.newton_failures, 0);
  EXPECT_NEAR(t.S, -1.0, 1e-6) << "b = 1: triaxial extension";
  EXPECT_NEAR(t.p / 200e3, 1.0, 1e-8);
  EXPECT_NEAR(t.eta / Me, 1.0, 5e-3);
  EXPECT_NEAR(t.e / ec_indep(f, t.p), 1.0, 5e-3);
  std::printf("TE (Sheng): q/p = %.5f (M_e %.5f = %.4f M_c), sin3theta %.7f, e/e_c %.5f\n", t.eta, Me,
              Me / Mc_of(f), t.S, t.e / ec_indep(f, t.p));
  const TriaxialEnd n = triaxial(table1(/*lode=*/false), 0.80, 200e3, Loading::drainedTrueTriaxial, 1.0, 0.6, 2e-4);
  EXPECT_NEAR(n.eta / Mc_of(f), 1.0, 5e-3) << "lodeDependence none: M_c in extension too";
  std::printf("TE (none):  q/p = %.5f (M_c %.5f)\n", n.eta, Mc_of(f));
}

// True triaxial at constant p and fixed b: the Lode angle is fixed by b (sin 3theta(b) above),
// and the critical state is q/p = M_c g(theta(b)): b = 0.5 is pure shear (sin 3theta = 0,
// g = (2c^4/(1 + c^4))^{1/4} = 0.802 at phi_c = 30 deg), b = 0.25 in between. Dense (0.80) and
// loose (0.93 > e_c(200 kPa) = 0.920) samples end at the same ratio.
TEST(Simsand3D, TrueTriaxialAtAnIntermediateLodeAngleReachesMcG) {
  const simsand::Params f = table1();
  for (const double b : {0.25, 0.5}) {
    for (const double e0 : {0.80, 0.93}) {
      const TriaxialEnd t = triaxial(f, e0, 200e3, Loading::drainedTrueTriaxial, b, 0.6, 2e-4);
      const double S = sin3theta_of_b(b), expected = Mc_of(f) * sheng_g(f, S);
      EXPECT_EQ(t.newton_failures, 0);
      EXPECT_NEAR(t.b, b, 1e-6) << "b held";
      EXPECT_NEAR(t.S, S, 1e-6) << "sin 3theta set by b";
      EXPECT_NEAR(t.eta / expected, 1.0, 5e-3) << "b " << b << " e0 " << e0;
      EXPECT_NEAR(t.e / ec_indep(f, t.p), 1.0, 5e-3) << "b " << b << " e0 " << e0;
      std::printf("b %.2f e0 %.2f: sin3theta %.6f (%.6f), q/p = %.5f (M_c g = %.5f), e/e_c %.5f\n", b, e0, t.S, S,
                  t.eta, expected, t.e / ec_indep(f, t.p));
    }
  }
}

// ---------------------------------------------------------------- isotropy of the 3D update

namespace {

using M3 = std::array<std::array<double, 3>, 3>;

/// A rotation taking the x-y plane to a general plane (Euler angles z-x-z).
M3 rotation(double a, double b, double c) {
  auto Rz = [](double t) { return M3{{{std::cos(t), -std::sin(t), 0}, {std::sin(t), std::cos(t), 0}, {0, 0, 1}}}; };
  auto Rx = [](double t) { return M3{{{1, 0, 0}, {0, std::cos(t), -std::sin(t)}, {0, std::sin(t), std::cos(t)}}}; };
  auto mul = [](const M3& A, const M3& B) {
    M3 C{};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        for (int k = 0; k < 3; ++k) C[i][j] += A[i][k] * B[k][j];
    return C;
  };
  return mul(mul(Rz(a), Rx(b)), Rz(c));
}
/// R A R^T of a full matrix.
M3 turn(const M3& R, const M3& A) {
  M3 C{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k)
        for (int l = 0; l < 3; ++l) C[i][j] += R[i][k] * A[k][l] * R[j][l];
  return C;
}
M3 full(const Sym3& s) {
  M3 A;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) A[i][j] = s(i, j);
  return A;
}
Sym3 sym(const M3& A) {
  return Sym3{{A[0][0], A[1][1], A[2][2], 0.5 * (A[0][1] + A[1][0]), 0.5 * (A[1][2] + A[2][1]),
               0.5 * (A[0][2] + A[2][0])}};
}
M3 transpose(const M3& R) {
  M3 T;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) T[i][j] = R[j][i];
  return T;
}
/// The increment of a velocity gradient L over dt, as the kernels form it (sym, skew).
StrainIncrement increment_of(const M3& L, double dt) {
  Mat<3> l;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) l(i, j) = L[i][j];
  StrainIncrement inc;
  inc.deps = sym3_from(l) * dt;
  inc.spin = spin_from(l);
  inc.spin.xy *= dt;
  inc.spin.yz *= dt;
  inc.spin.zx *= dt;
  inc.dt = dt;
  inc.J = 1;
  return inc;
}

struct Isotropy {
  double stress = 0;  ///< largest |sigma_2D - R^T sigma_3D R| over the history, relative to |sigma|
  double state = 0;   ///< largest relative difference of the scalar state
  Sym3 end2 = Sym3::zero(), end3 = Sym3::zero();
  std::vector<Real> state2, state3;
};

/// The plane-strain history (in-plane L, count, dt) in x-y and turned by R; compares after
/// every step. `scalar_state`: how many leading Reals of the state are scalars to compare
/// (tensor-valued state is compared through `tensor_state` when given).
template <class M>
Isotropy isotropy(const typename M::Params& mp, const Sym3& sigma0, const std::vector<std::pair<M3, int>>& history,
                  double dt, const M3& R, int scalar_first, int scalar_count) {
  PointMaterialOf<M> a(mp), b(mp);
  Sym3 s2 = sigma0, s3 = sym(turn(R, full(sigma0)));
  a.initialise(s2);
  b.initialise(s3);
  const M3 Rt = transpose(R);
  Isotropy r;
  for (const auto& [L, count] : history) {
    const StrainIncrement i2 = increment_of(L, dt), i3 = increment_of(turn(R, L), dt);
    for (int k = 0; k < count; ++k) {
      a.update(s2, i2);
      b.update(s3, i3);
      const Sym3 back = sym(turn(Rt, full(s3)));
      const double scale = std::max(norm(s2), 1e-300);
      for (int c = 0; c < 6; ++c) r.stress = std::max(r.stress, std::fabs(back[c] - s2[c]) / scale);
      const std::vector<Real> x2 = a.state(), x3 = b.state();
      for (int j = scalar_first; j < scalar_first + scalar_count; ++j)
        r.state = std::max(r.state, std::fabs(x2[j] - x3[j]) / std::max(std::fabs(x2[j]), 1e-300));
    }
  }
  r.end2 = s2;
  r.end3 = s3;
  r.state2 = a.state();
  r.state3 = b.state();
  return r;
}

M3 gradient(double l00, double l01, double l10, double l11) { return M3{{{l00, l01, 0}, {l10, l11, 0}, {0, 0, 0}}}; }

}  // namespace

// Simple shear in another plane of 3D space equals the 2D simple shear (kinetic theory): the
// collisional stress (eq. 19) is -p(e, T) I + 2 eta dev D + gamma tr(D) I and the temperature
// equation (eq. 27) sees D through tr D and dev D : dev D only, so the turned history must give
// the turned stress and the same T. Two planes: y-z (a plane the 2D code never sees) and a general
// one. Shear at 20 1/s to the steady state, then rest. Tolerance 1e-12 relative: the turned
// history differs by the round-off of turning D (a few ulps in dev D : dev D), which the
// temperature's stable (contracting) update does not amplify; the steady state is checked
// against the 2D run and against itself (T steady to 1e-10 over the last 10 % of the shear).
TEST(KineticTheory3D, SimpleShearInAnyPlaneEqualsThe2DSteadyShear) {
  const KineticTheory::Params P{table2(), 1 / 0.55 - 1, 1e-6};
  const double dt = 1e-4, gdot = 20;
  for (const M3& R : {rotation(0, 0.5 * kPi, 0.5 * kPi), rotation(0.3, 1.1, -0.7)}) {
    // steady shear: run it in two pieces to see that T has stopped changing
    const std::vector<std::pair<M3, int>> h1 = {{gradient(0, gdot, 0, 0), 9000}};
    const std::vector<std::pair<M3, int>> h2 = {{gradient(0, gdot, 0, 0), 10000}};
    const Isotropy r1 = isotropy<KineticTheory>(P, Sym3::zero(), h1, dt, R, 0, 2);
    const Isotropy r2 = isotropy<KineticTheory>(P, Sym3::zero(), h2, dt, R, 0, 2);
    EXPECT_LE(r2.stress, 1e-12);
    EXPECT_LE(r2.state, 1e-12);
    EXPECT_NEAR(r2.state2[1] / r1.state2[1], 1.0, 1e-10) << "steady T";
    // the shear stress on the turned plane and its normal stresses are the 2D ones: p, q, tau
    EXPECT_NEAR(pressure(r2.end3), pressure(r2.end2), 1e-12 * std::fabs(pressure(r2.end2)));
    EXPECT_NEAR(deviatoric_stress(r2.end3), deviatoric_stress(r2.end2), 1e-12 * deviatoric_stress(r2.end2));
    EXPECT_GT(r2.state2[1], 1e-6) << "the shear heated the grains";
    // then rest: T decays the same way
    const std::vector<std::pair<M3, int>> h3 = {{gradient(0, gdot, 0, 0), 2000}, {gradient(0, 0, 0, 0), 3000},
                                                {gradient(-0.5, 5, -2, 0.3), 500}};
    const Isotropy r3 = isotropy<KineticTheory>(P, Sym3::zero(), h3, dt, R, 0, 2);
    EXPECT_LE(r3.stress, 1e-12);
    EXPECT_LE(r3.state, 1e-12);
    std::printf("kinetic theory, turned plane: steady T %.6e m^2/s^2, p %.6g Pa, tau %.6g Pa; max rel. diff stress "
                "%.1e, T %.1e; decay+general %.1e %.1e\n",
                r2.state2[1], pressure(r2.end2), r2.end2[3], r2.stress, r2.state, r3.stress, r3.state);
  }
}

// SIMSAND's frictional history turned into general planes: compression, simple shear (with spin)
// to the critical state and its reversal, in the x-y plane and in two turned planes, with every
// stress component of the turned run active (J3 of the full tensor, the co-rotation with a general
// spin). The integrator decides its substeps from error estimates, so round-off differences
// between the two runs could change a substep decision and with it the result by up to the local
// tolerance STOL = 1e-4 (relative); bit-level agreement is not expected, agreement to a small
// multiple of round-off amplification is. Bound: 1e-10 relative in stress and state, 6 orders
// below what one changed substep decision would give (STOL) and 3 above the measured figures
// (2e-13 over the 1050 steps; printed).
TEST(Simsand3D, TurnedPlaneStrainHistoryGivesTheTurnedStress) {
  const std::vector<std::pair<M3, int>> h = {{gradient(-0.1, 0, 0, -0.1), 50},
                                             {gradient(0, 1, 0, 0), 600},
                                             {gradient(0, -1, 0, 0), 200},
                                             {gradient(-0.02, 0.5, -0.3, 0), 200}};
  for (const double e0 : {0.70, 0.90}) {
    const Simsand::Params P{table1(), 2650, e0};
    for (const M3& R : {rotation(0, 0.5 * kPi, 0.5 * kPi), rotation(0.3, 1.1, -0.7)}) {
      const Isotropy r = isotropy<Simsand>(P, k0_stress(100e3, 0.5), h, 1e-3, R, 0, 3);
      EXPECT_LE(r.stress, 1e-10) << "e0 " << e0;
      EXPECT_LE(r.state, 1e-10) << "e0 " << e0;
      std::printf("simsand e0 %.2f turned: max rel. diff stress %.1e, state (e, kappa, epsEq) %.1e; end q/p %.4f\n",
                  e0, r.stress, r.state, deviatoric_stress(r.end2) / pressure(r.end2));
    }
  }
}

// The same for phaseTransition, whose frictional stress is a tensor-valued state (co-rotated by
// the model itself, with the general spin here): sigma_f turned back equals the 2D one, with a
// fast shear phase (collisional stress) included.
TEST(PhaseTransition3D, TurnedPlaneStrainHistoryGivesTheTurnedStress) {
  const PhaseTransition::Params P{table3_collapse_f(), table3_collapse_c(), 0.80, 1e-6};
  const std::vector<std::pair<M3, int>> h = {{gradient(-0.1, 0, 0, -0.1), 50},
                                             {gradient(0, 1, 0, 0), 600},
                                             {gradient(-0.05, 10, 0, 0), 100},
                                             {gradient(0, 0, 0, 0), 100}};
  const M3 R = rotation(0.3, 1.1, -0.7);
  // State: sigf (6), e, T, epsEq, kappa, rate, trD: compare the scalars e .. kappa
  const Isotropy r = isotropy<PhaseTransition>(P, k0_stress(20e3, 0.5), h, 1e-3, R, 6, 4);
  EXPECT_LE(r.stress, 1e-10);
  EXPECT_LE(r.state, 1e-10);
  Sym3 f2, f3;
  for (int c = 0; c < 6; ++c) {
    f2[c] = r.state2[c];
    f3[c] = r.state3[c];
  }
  const Sym3 back = sym(turn(transpose(R), full(f3)));
  for (int c = 0; c < 6; ++c) EXPECT_NEAR(back[c], f2[c], 1e-10 * norm(f2)) << "sigma_f component " << c;
  std::printf("phaseTransition turned: max rel. diff stress %.1e, state %.1e, T %.4g\n", r.stress, r.state,
              r.state2[7]);
}
