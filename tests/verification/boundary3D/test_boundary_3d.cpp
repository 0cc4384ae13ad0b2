// Boundary conditions on a 3D grid.
//
// A block on a plane tilted about two axes. The plane's normal is (sin 30, cos 30, 0)
// turned 30 degrees about y: n = (0.433, 0.866, -0.25). Its slope is still 30 degrees
// (n . y = cos 30), and its downhill direction t = (-y + (n . y) n) / sin 30 = (0.75, -0.5,
// -0.433) has a component along every axis, so no pair of axes holds the motion, as it would
// on a plane tilted about one axis (the 2D case extruded). A rigid block on it slides with
// a = g (sin theta - mu cos theta) along t and stays for mu > tan 30 = 0.577, the classic
// check of frictional contact (Bardenhagen, Brackbill & Sulsky 2000), here as
// tests/verification/boundary/test_inclined_plane.cpp does in 2D: the `slip` and `friction`
// walls on a half-space, and the inclinedPlane plugin. The block (0.2 m along t, 0.05 m
// along n, 0.15 m across, an stl region: a parallelepiped that no other region type makes)
// is cut from the lattice of 0.025 m cells, 2 points per cell along each axis (1,300
// points), and stiff enough (E = 5e5 Pa: its weight strains it by 1e-3) that it slides as a
// whole; its normal modes (~ 130 Hz) average out of a least-squares fit of its mean
// velocity along t over 0.04-0.2 s. 2000 steps of 1e-4 s (Courant number 0.1 for the
// P-wave speed, 26 m/s). The frictional contact is sensitive to the step: with 2e-4 s a was
// 0.8% too large at mu = 0.4 (1.5% with 0.02 m cells, Courant 0.26), and with E = 1e7 at
// Courant 0.9 the contact rang the block off the plane (a 15% too large).
// Tolerance: 1% of a, as in 2D. Measured (printed by the test): slip 0.000% on either wall,
// mu = 0.2 +0.02%, mu = 0.4 +0.15% (the largest: the smallest a), the same on both walls.
// Motion confined to the plane's downhill direction: the centre of mass's travel across the
// slope (along t x n) and off the plane (along n) over the fit's window below 1% of its
// travel along t (the rigid block has none; the ringing, up to 1e-2 m/s at ~ 800 rad/s, moves
// it by ~ 1e-5 m, and its velocity, sampled every 0.01 s, aliases: hence positions).
// Measured: across below 0.07% of the travel; off the plane 0.54% at mu = 0.4 (0.16 mm
// over 30 mm: the base's staircase of points riding over the plane's nodes), 0.11% slip. A
// block held (mu = 0.7, noSlip) stays below
// 0.01 m/s after 0.2 s, against the 0.30 m/s it reaches with mu = 0.4 (measured: 5e-4 m/s).
//
// The runs use one thread (the 2D test's reasoning: a few thousand points do not share
// well on a busy 2-core machine).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "scree_test.hpp"
#include "stl_surfaces.hpp"

namespace scree::test {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kG = 9.81;
const double kTheta = 30 * kPi / 180;
const double kPhi = 30 * kPi / 180;  // the turn about y
// n = R_y(phi) (sin theta, cos theta, 0); t = (-y + n_y n) / sin theta; b = t x n.
const P3 kN = {std::sin(kTheta) * std::cos(kPhi), std::cos(kTheta), -std::sin(kTheta) * std::sin(kPhi)};
const P3 kT = {kN[1] * kN[0] / std::sin(kTheta), (-1 + kN[1] * kN[1]) / std::sin(kTheta),
               kN[1] * kN[2] / std::sin(kTheta)};
const P3 kB = {kT[1] * kN[2] - kT[2] * kN[1], kT[2] * kN[0] - kT[0] * kN[2], kT[0] * kN[1] - kT[1] * kN[0]};
const P3 kP0 = {0.1, 0.5, 0.45};  // a point on the plane

double dot(const P3& a, const P3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

std::string vec(const P3& p) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "(%.12g %.12g %.12g)", p[0], p[1], p[2]);
  return buf;
}

std::string half_space(const std::string& wall) {
  return wall + " halfSpace { point " + vec(kP0) + "; normal " + vec(kN) + "; }";
}
std::string inclined_plane(const std::string& condition) {
  return "type inclinedPlane; point " + vec(kP0) + "; normal " + vec(kN) + "; " + condition;
}

struct Velocity {
  double along, across, off;     ///< mean velocity along t, b and n
  double x_along, x_across, x_off;  ///< the centre of mass's position along t, b and n
};

/// The entries both blocks' cases share: the grid of 0.025 m cells over (0 0 0)-(0.6 height
/// 0.6), the step of 1e-4 s, USF with linear shape functions, gravity along -y and the block's
/// material (E = 5e5 Pa).
void write_lattice(const TempCase& tc, double height) {
  tc.write("system/controlDict", "endTime 1; deltaT 1e-4; writeInterval 1;");
  tc.write("system/gridDict", "dimension 3; lower (0 0 0); upper " + vec({0.6, height, 0.6}) + "; cellSize 0.025;");
  tc.write("system/mpmSchemes", "updateScheme USF; shapeFunction linear; transfer FLIP;");
  tc.write("constant/g", "value (0 -9.81 0);");
  tc.write("constant/materialProperties", "soil { type linearElastic; E 5e5; nu 0.3; rho 1000; }");
}

/// The block's mass-weighted mean velocity at each of `times`; `wall` the plane's entries.
std::vector<Velocity> slide(const std::string& wall, const std::vector<double>& times) {
  TempCase tc("inclined_plane_3d");
  write_lattice(tc, 0.6);
  // The block: from 0.02 to 0.22 m down the slope of kP0, 0 to 0.05 m above the plane, -0.075
  // to 0.075 m across.
  std::filesystem::create_directories(tc.dir() / "constant/triSurface");
  write_ascii_stl((tc.dir() / "constant/triSurface/block.stl").string(), hexahedron([](int i, int j, int k) {
                    const double s = 0.02 + 0.2 * i, h = 0.05 * j, c = -0.075 + 0.15 * k;
                    return P3{kP0[0] + s * kT[0] + h * kN[0] + c * kB[0], kP0[1] + s * kT[1] + h * kN[1] + c * kB[1],
                              kP0[2] + s * kT[2] + h * kN[2] + c * kB[2]};
                  }));
  tc.write("constant/bodies",
           "block { material soil; region { type stl; file \"constant/triSurface/block.stl\"; } particlesPerCell 2; }");
  // The ground of the terrain condition: the solid under the plane, from y = -1 to the
  // plane, over more than the domain's footprint.
  write_ascii_stl((tc.dir() / "constant/triSurface/ground.stl").string(), hexahedron([](int i, int j, int k) {
                    const double x = -0.1 + 0.8 * i, z = -0.1 + 0.8 * k;
                    const double y = j ? kP0[1] - (kN[0] * (x - kP0[0]) + kN[2] * (z - kP0[2])) / kN[1] : -1.0;
                    return P3{x, y, z};
                  }));
  tc.write("constant/boundaryConditions", "plane { " + wall + " }");
  std::vector<Velocity> out;
  for (const BodyMotion& mo : body_motion(tc, times))
    out.push_back({dot(mo.v, kT), dot(mo.v, kB), dot(mo.v, kN), dot(mo.x, kT), dot(mo.x, kB), dot(mo.x, kN)});
  return out;
}

/// The least-squares acceleration along t.
double fit_acceleration(const std::vector<double>& t, const std::vector<Velocity>& v) {
  std::vector<double> along;
  for (const Velocity& vi : v) along.push_back(vi.along);
  return least_squares_slope(t, along);
}

void expect_slides(const std::string& wall, double mu) {
  std::vector<double> t;
  for (int k = 0; k <= 16; ++k) t.push_back(0.04 + 0.01 * k);
  const std::vector<Velocity> v = slide(wall, t);
  const double a = fit_acceleration(t, v);
  const double exact = kG * (std::sin(kTheta) - mu * std::cos(kTheta));
  // The centre of mass's travel over the fit's window.
  const double along = v.back().x_along - v.front().x_along, across = v.back().x_across - v.front().x_across,
               off = v.back().x_off - v.front().x_off;
  std::printf("%s: a = %.5f m/s^2, rigid block %.5f m/s^2 (%+.3f%%); over 0.04-0.2 s the centre of mass moved "
              "%.4f m along, %.2e m across, %.2e m off the plane\n",
              wall.c_str(), a, exact, 100 * (a / exact - 1), along, across, off);
  EXPECT_NEAR(a, exact, 0.01 * exact) << wall;
  EXPECT_LT(std::fabs(across), 0.01 * along) << wall << ": motion across the slope";
  EXPECT_LT(std::fabs(off), 0.01 * along) << wall << ": motion off the plane";
}

void expect_stays(const std::string& wall) {
  const Velocity v = slide(wall, {0.2}).at(0);
  // With mu = 0.4 the block would be at 0.2 x 1.51 = 0.30 m/s; 0.01 m/s is the ringing's order.
  std::printf("%s: velocity along %.2e, across %.2e, off %.2e m/s after 0.2 s\n", wall.c_str(), v.along, v.across,
              v.off);
  EXPECT_LT(std::fabs(v.along), 0.01) << wall << ": the block must stay";
  EXPECT_LT(std::fabs(v.across), 0.01) << wall;
}

std::string friction(double mu) { return "type friction; coefficient " + std::to_string(mu) + ";"; }
std::string coulomb(double mu) { return "condition friction; coefficient " + std::to_string(mu) + ";"; }

TEST(InclinedPlane3D, TheDownhillDirectionHasAComponentAlongEveryAxis) {
  // The set-up's own geometry: unit n and t, t downhill, slope 30 degrees.
  EXPECT_NEAR(dot(kN, kN), 1, 1e-12);
  EXPECT_NEAR(dot(kT, kT), 1, 1e-12);
  EXPECT_NEAR(dot(kT, kN), 0, 1e-12);
  EXPECT_NEAR(-kT[1], std::sin(kTheta), 1e-12);  // g . t = g sin theta
  for (int d = 0; d < 3; ++d) EXPECT_GT(std::fabs(kT[d]), 0.4) << d;
}

TEST(InclinedPlane3D, AFrictionlessHalfSpaceLetsTheBlockSlideAtGSinTheta) { expect_slides(half_space("type slip;"), 0); }

TEST(InclinedPlane3D, CoulombFrictionOnAHalfSpaceTakesMuGCosTheta) {
  for (double mu : {0.2, 0.4}) expect_slides(half_space(friction(mu)), mu);
}

TEST(InclinedPlane3D, FrictionAboveTanThetaHoldsTheBlock) { expect_stays(half_space(friction(0.7))); }

// The terrain condition (boundary/terrain) on the same plane, read as the top of an STL
// solid: its nodes are those of the half-space (the nodes at or below the plane), each
// with the normal of the triangle above it, so the block slides as on the half-space wall.
std::string terrain(double mu) {
  return "type terrain; file \"constant/triSurface/ground.stl\"; coefficient " + std::to_string(mu) + ";";
}

TEST(Terrain3D, AGroundReadFromAnStlSolidSlidesTheBlockAtGSinThetaMinusMuGCosTheta) {
  for (double mu : {0.0, 0.4}) expect_slides(terrain(mu), mu);
}

TEST(Terrain3D, FrictionAboveTanThetaOrNoSlipHoldsTheBlock) {
  expect_stays(terrain(0.7));
  expect_stays("type terrain; file \"constant/triSurface/ground.stl\"; condition noSlip;");
}

TEST(Terrain3D, ConditionSlipIsFrictionless) {
  expect_slides("type terrain; file \"constant/triSurface/ground.stl\"; condition slip;", 0);
}

// The same STL as a solid of any shape (shape solid): every node inside it or on its
// surface, with the outward normal of the nearest face, which under the block is the
// plane's: the block slides as on the half-space, within the same 1%.
TEST(Terrain3D, TheGroundReadAsASolidOfAnyShapeSlidesTheBlockAlike) {
  expect_slides("type terrain; shape solid; file \"constant/triSurface/ground.stl\"; condition slip;", 0);
  expect_slides("type terrain; shape solid; file \"constant/triSurface/ground.stl\"; coefficient 0.4;", 0.4);
}

// A block in a V-shaped valley. The valley runs along x, its flanks rise at alpha = 30
// degrees on either side of the thalweg (z = 0.05 + tan(alpha) |y - 0.3|), and gravity is
// tilted by theta = 30 degrees down the valley, g = 9.81 (sin theta, 0, -cos theta), so
// the valley's axis is a grid axis and the block an extruded pentagon (a V-shaped base
// on both flanks, 0.2 m long). By symmetry each flank pushes with N = m g cos(theta) /
// (2 cos(alpha)) along its normal, and Coulomb friction on both takes 2 mu N: a rigid block
// slides with a = g (sin theta - mu cos theta / cos alpha). The ground is a pentagonal
// prism read as the top of an STL solid; the nodes of the thalweg take one flank's
// normal (the first of the two crossings at equal height), the block's V tip the other's
// on its neighbours. The same step, material and 1% tolerance as the plane above; the
// block stays on the valley's axis (its centre's travel across below 1% of its travel).
// Measured: mu = 0 exact to 5 digits, mu = 0.2 +0.19%; across 9e-5 and 5e-5 m over 0.094
// and 0.058 m.
void expect_slides_in_valley(double mu) {
  const double alpha = 30 * kPi / 180, s = std::tan(alpha);
  TempCase tc("v_valley_3d");
  tc.write("system/controlDict", "endTime 1; deltaT 1e-4; writeInterval 1;");
  tc.write("system/gridDict", "dimension 3; lower (0 0 0); upper (0.6 0.6 0.4); cellSize 0.025;");
  tc.write("system/mpmSchemes", "updateScheme USF; shapeFunction linear; transfer FLIP;");
  tc.write("constant/g", "value " + vec({kG * std::sin(kTheta), 0, -kG * std::cos(kTheta)}) + ";");
  tc.write("constant/materialProperties", "soil { type linearElastic; E 5e5; nu 0.3; rho 1000; }");
  // The ground: the prism under z = 0.05 + s |y - 0.3| over x in [-0.1, 0.7], y in [-0.1, 0.7].
  const double y0 = -0.1, y1 = 0.7, yc = 0.3, base = -0.3;
  auto top = [&](double y) { return 0.05 + s * std::fabs(y - yc); };
  const double ys[5][2] = {{y0, base}, {y1, base}, {y1, top(y1)}, {yc, top(yc)}, {y0, top(y0)}};
  auto at = [&](double x, int k) { return P3{x, ys[k][0], ys[k][1]}; };
  std::vector<Tri> tris;
  for (int k = 1; k + 1 < 5; ++k) {  // the end caps, fans of the pentagon (outward: -x, +x)
    tris.push_back({at(-0.1, 0), at(-0.1, k + 1), at(-0.1, k)});
    tris.push_back({at(0.7, 0), at(0.7, k), at(0.7, k + 1)});
  }
  for (int k = 0; k < 5; ++k) {  // the sides
    const int m = (k + 1) % 5;
    tris.push_back({at(-0.1, k), at(-0.1, m), at(0.7, m)});
    tris.push_back({at(-0.1, k), at(0.7, m), at(0.7, k)});
  }
  std::filesystem::create_directories(tc.dir() / "constant/triSurface");
  write_ascii_stl((tc.dir() / "constant/triSurface/valley.stl").string(), tris);
  char body[512];
  std::snprintf(body, sizeof body,
                "block { material soil; particlesPerCell 2; region { type extrudedPolygon; axis x; range (0.05 0.25); "
                "points ((0.2 %.12g) (0.3 0.05) (0.4 %.12g) (0.4 0.2) (0.2 0.2)); } }",
                top(0.2), top(0.4));
  tc.write("constant/bodies", body);
  tc.write("constant/boundaryConditions", "valley { type terrain; file \"constant/triSurface/valley.stl\"; "
                                          "coefficient " + std::to_string(mu) + "; up z; }");
  std::vector<double> t;
  for (int k = 0; k <= 16; ++k) t.push_back(0.04 + 0.01 * k);
  std::vector<double> along;
  const std::vector<BodyMotion> m = body_motion(tc, t);
  for (const BodyMotion& mo : m) along.push_back(mo.v[0]);
  const double a = least_squares_slope(t, along);
  const double exact = kG * (std::sin(kTheta) - mu * std::cos(kTheta) / std::cos(alpha));
  const double travel = m.back().x[0] - m.front().x[0], across = m.back().x[1] - m.front().x[1];
  std::printf("V-shaped valley, mu = %g: a = %.5f m/s^2, rigid block %.5f m/s^2 (%+.3f%%); over 0.04-0.2 s the "
              "centre of mass moved %.4f m along, %.2e m across\n",
              mu, a, exact, 100 * (a / exact - 1), travel, across);
  EXPECT_NEAR(a, exact, 0.01 * exact) << "mu = " << mu;
  EXPECT_LT(std::fabs(across), 0.01 * travel) << "mu = " << mu << ": motion across the valley";
}

TEST(Terrain3D, ABlockInAVShapedValleySlidesAtGSinThetaMinusMuGCosThetaOverCosAlpha) {
  for (double mu : {0.0, 0.2}) expect_slides_in_valley(mu);
}

TEST(InclinedPlanePlugin3D, SlipAndCoulombFriction) {
  expect_slides(inclined_plane("condition slip;"), 0);
  for (double mu : {0.2, 0.4}) expect_slides(inclined_plane(coulomb(mu)), mu);
}

TEST(InclinedPlanePlugin3D, FrictionAboveTanThetaOrNoSlipHoldsTheBlock) {
  expect_stays(inclined_plane(coulomb(0.7)));
  expect_stays(inclined_plane("condition noSlip;"));
}


// ---- a block moving over the floor of a 3D domain: faces and boxes ---------------------
//
// A block (0.2 x 0.05 x 0.2 m, a box region) on the floor y = 0, thrown at v0 = 1 m/s along
// (0.6, 0, 0.8): across both horizontal axes. On a `slip` face it keeps v0; with Coulomb
// friction mu (a `friction` face) it decelerates at mu g along -v0, keeping its direction;
// on a `fixed` box of nodes (every node of the floor and below it) its base sticks and it
// stops. Same lattice, material and step as above; the same 1% tolerance on the
// deceleration, and on the velocity kept; sideways (across v0) below 1% of |v0|. Measured:
// slip keeps 1.0000 m/s; mu = 0.3 decelerates at 2.953 m/s^2 against 2.943 (+0.35%),
// sideways below 4e-5 m/s; the fixed box holds the centre of mass within 1.1 mm.

const P3 kDir = {0.6, 0, 0.8};

/// The block's mass-weighted mean velocity and centre of mass at each of `times`.
std::vector<BodyMotion> throw_block(const std::string& floor, const std::vector<double>& times) {
  TempCase tc("floor_3d");
  write_lattice(tc, 0.2);
  tc.write("constant/bodies", "block { material soil; region { type box; lower (0.05 0 0.05); upper (0.25 0.05 0.25); } "
                              "velocity " + vec(kDir) + "; particlesPerCell 2; }");
  tc.write("constant/boundaryConditions", "floor { " + floor + " }");
  return body_motion(tc, times);
}

/// The deceleration along kDir fitted over 0.02-0.1 s, and the largest sideways velocity.
void expect_decelerates(const std::string& floor, double expected) {
  std::vector<double> t;
  for (int k = 0; k <= 16; ++k) t.push_back(0.02 + 0.005 * k);
  const std::vector<BodyMotion> m = throw_block(floor, t);
  std::vector<double> along;
  double sideways = 0;
  for (const BodyMotion& mo : m) {
    const P3& x = mo.v;
    along.push_back(dot(x, kDir));
    sideways = std::max(sideways, std::fabs(x[0] * kDir[2] - x[2] * kDir[0]));
  }
  const double a = -least_squares_slope(t, along);
  std::printf("%s: deceleration %.5f m/s^2 (expected %.5f); velocity along v0 at 0.1 s %.4f m/s, sideways at "
              "most %.2e m/s\n",
              floor.c_str(), a, expected, along.back(), sideways);
  if (expected == 0)
    EXPECT_NEAR(along.back(), 1.0, 0.01) << floor;
  else
    EXPECT_NEAR(a, expected, 0.01 * expected) << floor;
  EXPECT_LT(sideways, 0.01) << floor;
}

TEST(Floor3D, ASlipFaceKeepsTheVelocityAlongBothHorizontalAxes) { expect_decelerates("type slip; face yMin;", 0); }

TEST(Floor3D, AFrictionFaceDeceleratesAtMuGAgainstTheVelocity) {
  expect_decelerates("type friction; face yMin; coefficient 0.3;", 0.3 * kG);
}

TEST(Floor3D, AFixedBoxOfNodesStopsTheBlock) {
  // The base sticks; the block sways on it (a shear mode of ~ 70 Hz, amplitude ~ v0 / omega
  // = 2 mm at its top) but its centre of mass does not travel: below 1 cm from 0.02 to 0.2 s,
  // where on the slip face it travels 0.18 m.
  const std::vector<BodyMotion> m = throw_block("type fixed; box { min (-0.1 -0.1 -0.1); max (0.7 0 0.7); }", {0.02, 0.2});
  const P3 d = {m[1].x[0] - m[0].x[0], m[1].x[1] - m[0].x[1], m[1].x[2] - m[0].x[2]};
  std::printf("fixed box: the centre of mass moved (%.2e %.2e %.2e) m from 0.02 to 0.2 s\n", d[0], d[1], d[2]);
  EXPECT_LT(std::sqrt(dot(d, d)), 0.01);
}

}  // namespace
}  // namespace scree::test

SCREE_TEST_MAIN()
