// An elastic block on a rigid plane inclined at 30 degrees to the grid (a `friction` or `slip`
// wall on a half-space; mpm/wall_law.hpp): with Coulomb friction mu below tan 30 = 0.577 the
// block slides with the acceleration of a rigid block, a = g (sin 30 - mu cos 30); above it,
// it stays. The classic check of a frictional contact (Bardenhagen, Brackbill & Sulsky 2000),
// here on a plane that cuts the grid's cells at an angle.
//
// The block (0.2 m x 0.05 m, E = 1e7 Pa) is stiff: its normal and bending modes ring at
// hundreds of Hz and average out of a least-squares fit of its mean along-slope velocity over
// 0.05-0.3 s. Measured: within 0.1% of a for mu = 0, 0.2 and 0.4 (USF and MUSL); the
// tolerance, 1% of a, is for the ringing's share of the fit. A block held by mu = 0.7 stays
// (below 1e-5 m/s after 0.3 s, against the 0.45 m/s it would reach with mu = 0.4).
//
// Not covered, because not reproduced (2026-11-25): a friction wall that is not separable
// (a = 2.70 instead of 3.21 m/s^2 for mu = 0.2; the block sticks for mu = 0.4: the law takes
// mu |v_n| of every node it holds, the ringing's pulls included), and the USL update, with
// which the block blows up within 0.035 s on this plane (USF and MUSL are used here).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "scree_test.hpp"

namespace scree::test {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kG = 9.81;
const double kTheta = 30 * kPi / 180;
// Down the slope, and the plane's normal into the material.
const double kT[2] = {std::cos(kTheta), -std::sin(kTheta)};
const double kN[2] = {std::sin(kTheta), std::cos(kTheta)};

std::string point(double s, double h) {  // s down the slope from (0, 0.7), h above it
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.12g %.12g)", s * kT[0] + h * kN[0], 0.7 + s * kT[1] + h * kN[1]);
  return buf;
}

/// The block's mass-weighted mean velocity along the slope at each of `times`.
std::vector<double> slide(const std::string& wall, const std::string& scheme, const std::vector<double>& times) {
  TempCase tc("inclined_plane");
  tc.write("system/controlDict", "endTime 1; deltaT 2e-5; writeInterval 1;");
  tc.write("system/gridDict", "dimension 2; lower (0 0); upper (1.2 0.8); cellSize 0.01;");
  tc.write("system/mpmSchemes", "updateScheme " + scheme + "; shapeFunction linear; transfer FLIP;");
  tc.write("constant/g", "value (0 -9.81);");
  tc.write("constant/materialProperties", "soil { type linearElastic; E 1e7; nu 0.3; rho 1000; }");
  tc.write("constant/bodies", "block { material soil; region { type polygon; points (" + point(0.1, 0) + " " +
                                  point(0.3, 0) + " " + point(0.3, 0.05) + " " + point(0.1, 0.05) +
                                  "); } particlesPerCell 2; }");
  char plane[160];
  std::snprintf(plane, sizeof plane, "halfSpace { point (0 0.7); normal (%.12g %.12g); }", kN[0], kN[1]);
  tc.write("constant/boundaryConditions", "plane { " + wall + " " + plane + " }");
  Case c = Case::read(tc.dir(), runtime());
  Simulation sim(c, runtime(), options());
  std::vector<double> out;
  for (double t : times) {
    sim.advance_to(t);
    const Snapshot s = sim.snapshot();
    const BodySnapshot& b = s.bodies.at(0);
    const auto& v = b.find("velocity")->values;
    const auto& m = b.find("mass")->values;
    double p = 0, mass = 0;
    for (Index i = 0; i < b.n; ++i) {
      p += m[i] * (v[3 * i] * kT[0] + v[3 * i + 1] * kT[1]);
      mass += m[i];
    }
    out.push_back(p / mass);
  }
  return out;
}

/// Least-squares slope of v(t).
double fit_acceleration(const std::vector<double>& t, const std::vector<double>& v) {
  double st = 0, sv = 0, stt = 0, stv = 0;
  const double n = static_cast<double>(t.size());
  for (std::size_t i = 0; i < t.size(); ++i) {
    st += t[i];
    sv += v[i];
    stt += t[i] * t[i];
    stv += t[i] * v[i];
  }
  return (n * stv - st * sv) / (n * stt - st * st);
}

std::vector<double> fit_times() {
  std::vector<double> t;
  for (int k = 0; k <= 25; ++k) t.push_back(0.05 + 0.01 * k);
  return t;
}

void expect_slides(const std::string& wall, double mu, const std::string& scheme) {
  const std::vector<double> t = fit_times();
  const double a = fit_acceleration(t, slide(wall, scheme, t));
  const double exact = kG * (std::sin(kTheta) - mu * std::cos(kTheta));
  std::printf("%s, %s: a = %.5f m/s^2, rigid block %.5f m/s^2 (%+.3f%%)\n", wall.c_str(), scheme.c_str(), a, exact,
              100 * (a / exact - 1));
  EXPECT_NEAR(a, exact, 0.01 * exact) << wall << ", " << scheme;
}

TEST(InclinedPlane, AFrictionlessPlaneLetsTheBlockSlideAtGSinTheta) {
  expect_slides("type slip;", 0, "USF");
  expect_slides("type slip;", 0, "MUSL");
}

TEST(InclinedPlane, CoulombFrictionTakesMuGCosTheta) {
  for (double mu : {0.2, 0.4}) expect_slides("type friction; coefficient " + std::to_string(mu) + ";", mu, "USF");
  expect_slides("type friction; coefficient 0.2;", 0.2, "MUSL");
}

TEST(InclinedPlane, FrictionAboveTanThetaHoldsTheBlock) {
  const std::vector<double> t = {0.3};
  const double v = slide("type friction; coefficient 0.7;", "USF", t).at(0);
  std::printf("mu 0.7: along-slope velocity %.5f m/s after 0.3 s\n", v);
  EXPECT_LT(std::fabs(v), 0.02) << "mu = 0.7 > tan 30 deg = 0.577: the block must stay";
}

}  // namespace
}  // namespace scree::test

SCREE_TEST_MAIN()
