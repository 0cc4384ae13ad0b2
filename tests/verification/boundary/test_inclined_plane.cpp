// An elastic block on a rigid plane inclined at 30 degrees to the grid: with Coulomb
// friction mu below tan 30 = 0.577 the block slides with the acceleration of a rigid block,
// a = g (sin 30 - mu cos 30); above it, it stays. The classic check of a frictional contact
// (Bardenhagen, Brackbill & Sulsky 2000), here on a plane that cuts the grid's cells at an
// angle, made twice: with the `slip` and `friction` walls on a half-space (every node behind
// the plane; mpm/wall_law.hpp), and with the `inclinedPlane` plugin (the contact law on the
// nodes behind the plane that points in front of it reach, the nodes further behind held:
// boundary/inclinedPlane), and once more with a `terrain` ground drawn as a polyline.
//
// The block (0.2 m x 0.05 m, E = 1e7 Pa) is stiff: its normal and bending modes ring at
// hundreds of Hz and average out of a least-squares fit of its mean along-slope velocity over
// 0.05-0.3 s. Measured: within 0.1% of a for mu = 0, 0.2 and 0.4 (USF and MUSL; both walls;
// linear shape functions, and bspline2 for mu = 0.2); the tolerance, 1% of a, is for the
// ringing's share of the fit. A block held by mu = 0.7 stays (below 1e-5 m/s after 0.3 s,
// against the 0.45 m/s it would reach with mu = 0.4), on a noSlip plane below 3e-4 m/s. On
// this plane the two walls give the same a to the last digit printed: no point goes deep
// enough through the plane to weigh on the nodes the plugin holds; which nodes each of its
// sets takes is checked on its own (ActsOnTheNodesInReachAndHoldsTheNodesBehind). The
// bspline2 run guards the depth of the contact set: holding the nodes that bspline2 points
// in front of the plane weigh on (1.5 cells), not only the linear functions' (1 cell), took
// 24% off a.
//
// The runs use one thread: 400 points are too few to share, and on a 2-core machine busy
// with other builds, as CI's can be, two threads wait on each other far longer than they
// save.
//
// Not covered, because not reproduced: a friction wall that is not separable
// (a = 2.70 instead of 3.21 m/s^2 for mu = 0.2; the block sticks for mu = 0.4: the law takes
// mu |v_n| of every node it holds, the ringing's pulls included), and the USL update, with
// which the block blows up within 0.035 s on this plane, with either wall. That is USL's own:
// the same block falling freely, far from any wall, blows up by 0.023 s, at 30
// degrees or aligned with the grid: its stress comes from the updated velocity of nodes at
// the block's edge whose mass is a small share of a point's (massTolerance 1e-6) and whose
// f/m is not; with massTolerance 1e-2 the free fall holds (to 0.1 s), the slide still blows
// up (0.055 s on the plugin's slip plane, 0.079 s on the halfSpace slip wall); with 1e-1 it
// slides without blowing up but too slowly, since the nodes along the plane it leaves
// unaccelerated are many. USF and MUSL are used here, and USL with GIMP.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <regex>
#include <string>
#include <vector>

#include "scree/boundary/boundary_condition.hpp"
#include "scree/plugin/context.hpp"
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

/// The plane as a wall of `type ...;` on a half-space: every node on or behind it.
std::string half_space(const std::string& wall) {
  char plane[160];
  std::snprintf(plane, sizeof plane, " halfSpace { point (0 0.7); normal (%.12g %.12g); }", kN[0], kN[1]);
  return wall + plane;
}

/// The plane as the inclinedPlane plugin with `condition ...;`.
std::string inclined_plane(const std::string& condition) {
  char plane[160];
  std::snprintf(plane, sizeof plane, "type inclinedPlane; point (0 0.7); normal (%.12g %.12g); ", kN[0], kN[1]);
  return plane + condition;
}

/// The block's mass-weighted mean velocity along the slope at each of `times`; `wall` is the
/// entries of the plane's boundary condition.
std::vector<double> slide(const std::string& wall, const std::string& scheme, const std::vector<double>& times,
                          const std::string& shape = "linear") {
  TempCase tc("inclined_plane");
  tc.write("system/controlDict", "endTime 1; deltaT 2e-5; writeInterval 1;");
  tc.write("system/gridDict", "dimension 2; lower (0 0); upper (1.2 0.8); cellSize 0.01;");
  tc.write("system/mpmSchemes", "updateScheme " + scheme + "; shapeFunction " + shape + "; transfer FLIP;");
  tc.write("constant/g", "value (0 -9.81);");
  tc.write("constant/materialProperties", "soil { type linearElastic; E 1e7; nu 0.3; rho 1000; }");
  tc.write("constant/bodies", "block { material soil; region { type polygon; points (" + point(0.1, 0) + " " +
                                  point(0.3, 0) + " " + point(0.3, 0.05) + " " + point(0.1, 0.05) +
                                  "); } particlesPerCell 2; }");
  tc.write("constant/boundaryConditions", "plane { " + wall + " }");
  std::vector<double> out;
  for (const BodyMotion& mo : body_motion(tc, times)) out.push_back(mo.v[0] * kT[0] + mo.v[1] * kT[1]);
  return out;
}

std::vector<double> fit_times() {
  std::vector<double> t;
  for (int k = 0; k <= 25; ++k) t.push_back(0.05 + 0.01 * k);
  return t;
}

void expect_slides(const std::string& wall, double mu, const std::string& scheme,
                   const std::string& shape = "linear") {
  const std::vector<double> t = fit_times();
  const double a = least_squares_slope(t, slide(wall, scheme, t, shape));
  const double exact = kG * (std::sin(kTheta) - mu * std::cos(kTheta));
  std::printf("%s, %s, %s: a = %.5f m/s^2, rigid block %.5f m/s^2 (%+.3f%%)\n", wall.c_str(), scheme.c_str(),
              shape.c_str(), a, exact, 100 * (a / exact - 1));
  EXPECT_NEAR(a, exact, 0.01 * exact) << wall << ", " << scheme << ", " << shape;
}

void expect_stays(const std::string& wall, const std::string& scheme) {
  const std::vector<double> t = {0.3};
  const double v = slide(wall, scheme, t).at(0);
  std::printf("%s, %s: along-slope velocity %.5f m/s after 0.3 s\n", wall.c_str(), scheme.c_str(), v);
  EXPECT_LT(std::fabs(v), 0.02) << wall << ", " << scheme << ": the block must stay";
}

std::string friction(double mu) { return "type friction; coefficient " + std::to_string(mu) + ";"; }
std::string coulomb(double mu) { return "condition friction; coefficient " + std::to_string(mu) + ";"; }

TEST(InclinedPlane, AFrictionlessPlaneLetsTheBlockSlideAtGSinTheta) {
  expect_slides(half_space("type slip;"), 0, "USF");
  expect_slides(half_space("type slip;"), 0, "MUSL");
}

TEST(InclinedPlane, CoulombFrictionTakesMuGCosTheta) {
  for (double mu : {0.2, 0.4}) expect_slides(half_space(friction(mu)), mu, "USF");
  expect_slides(half_space(friction(0.2)), 0.2, "MUSL");
}

// USL itself is not the fault of the linear functions' blow-up above: with GIMP, whose
// domains leave no node with a sliver of a point's mass, it slides as USF and MUSL do.
TEST(InclinedPlane, USLWithGimpSlidesAsTheOtherSchemes) {
  expect_slides(half_space("type slip;"), 0, "USL", "gimp");
  expect_slides(half_space(friction(0.2)), 0.2, "USL", "gimp");
}

TEST(InclinedPlane, FrictionAboveTanThetaHoldsTheBlock) {
  expect_stays(half_space(friction(0.7)), "USF");  // mu = 0.7 > tan 30 deg = 0.577
}

TEST(InclinedPlanePlugin, SlipLetsTheBlockSlideAtGSinTheta) {
  for (const char* scheme : {"USF", "MUSL"}) expect_slides(inclined_plane("condition slip;"), 0, scheme);
}

TEST(InclinedPlanePlugin, CoulombFrictionTakesMuGCosTheta) {
  for (const char* scheme : {"USF", "MUSL"})
    for (double mu : {0.2, 0.4}) expect_slides(inclined_plane(coulomb(mu)), mu, scheme);
  expect_slides(inclined_plane(coulomb(0.2)), 0.2, "USF", "bspline2");
}

TEST(InclinedPlanePlugin, FrictionAboveTanThetaOrNoSlipHoldsTheBlock) {
  for (const char* scheme : {"USF", "MUSL"}) expect_stays(inclined_plane(coulomb(0.7)), scheme);
  expect_stays(inclined_plane("condition noSlip;"), "USF");
}

// The terrain condition (boundary/terrain) with the plane as a 2D ground, a polyline of
// three collinear vertices from above the domain's left edge to below its right one: its
// nodes are the half-space's (the nodes at or below the line), each with the segment's
// normal, so the block slides as on the half-space wall, within the same 1%.
std::string terrain(const std::string& condition) {
  return "type terrain; points (" + point(-0.2, 0) + " " + point(0.6, 0) + " " + point(1.6, 0) + "); " + condition;
}

TEST(Terrain2D, APolylineGroundSlidesTheBlockAsTheInclinedPlane) {
  expect_slides(terrain("condition slip;"), 0, "USF");
  for (double mu : {0.2, 0.4}) expect_slides(terrain(coulomb(mu)), mu, "USF");
  expect_slides(terrain(coulomb(0.2)), 0.2, "MUSL");
}

TEST(Terrain2D, FrictionAboveTanThetaOrNoSlipHoldsTheBlock) {
  expect_stays(terrain(coulomb(0.7)), "USF");
  expect_stays(terrain("condition noSlip;"), "USF");
}

// The same ground as a solid of any shape (shape solid): the parallelogram under the plane,
// 1 m deep, as a closed polygon. Its nodes are those inside it or on its edges, each with
// the normal of the nearest edge: under the block, the plane's, so the block slides as on
// the half-space wall, within the same 1%.
std::string terrain_solid(const std::string& condition) {
  return "type terrain; shape solid; points (" + point(-0.2, 0) + " " + point(1.6, 0) + " " + point(1.6, -1) + " " +
         point(-0.2, -1) + "); " + condition;
}

TEST(Terrain2D, APolygonSolidUnderTheBlockSlidesItAsTheInclinedPlane) {
  expect_slides(terrain_solid("condition slip;"), 0, "USF");
  expect_slides(terrain_solid(coulomb(0.2)), 0.2, "USF");
  expect_stays(terrain_solid(coulomb(0.7)), "USF");
}

// A retaining wall: a solid that is not a height field, here a vertical wall (the polygon
// left of x = 0.2 m), against which an elastic block is thrown at (-1, 0.2) m/s without
// gravity; beside it the slip wall on the half-space x <= 0.2, the same nodes. What holds for
// any frictionless rigid wall: it stops the block's approach (the block's centre stays at
// least half its width, 0.05 m, less a cell from the face), it sends the block back (its
// mean vx > 0 once the contact is over), and it takes no momentum along itself (the mean vy
// stays 0.2 m/s within 1e-3 of it: what the grid's small-mass nodes lose, measured 3.5e-4
// on the half-space wall). The rebound's speed is the contact's own dissipation and differs
// between the two (measured: 0.946 m/s off the solid, 0.863 m/s off the half-space): the
// terrain's node law acts after the grid update on both velocities the update produced, the
// wall inside the update; the test does not compare them.
std::vector<BodyMotion> thrown(const std::string& wall, const std::vector<double>& times) {
  TempCase tc("retaining_wall");
  tc.write("system/controlDict", "endTime 1; deltaT 2e-5; writeInterval 1;");
  tc.write("system/gridDict", "dimension 2; lower (0 0); upper (0.6 0.4); cellSize 0.01;");
  tc.write("system/mpmSchemes", "updateScheme USF; shapeFunction linear; transfer FLIP;");
  tc.write("constant/g", "value (0 0);");
  tc.write("constant/materialProperties", "soil { type linearElastic; E 1e7; nu 0.3; rho 1000; }");
  tc.write("constant/bodies", "block { material soil; region { type rectangle; lower (0.3 0.1); upper (0.4 0.2); } "
                              "particlesPerCell 2; velocity (-1 0.2); }");
  tc.write("constant/boundaryConditions", "wall { " + wall + " }");
  return body_motion(tc, times);
}

TEST(Terrain2D, AVerticalSolidWallStopsTheBlockAndSendsItBack) {
  const std::vector<double> t = {0.05, 0.1, 0.15, 0.2, 0.25};
  for (const char* wall : {"type terrain; shape solid; condition slip; points ((-0.1 -0.1) (0.2 -0.1) (0.2 0.5) "
                           "(-0.1 0.5));",
                           "type slip; halfSpace { point (0.2 0); normal (1 0); }"}) {
    const auto m = thrown(wall, t);
    for (std::size_t k = 0; k < t.size(); ++k) {
      std::printf("%s t = %.2f s: vx %.6f vy %.6f, centre x %.5f\n", wall, t[k], m[k].v[0], m[k].v[1], m[k].x[0]);
      EXPECT_NEAR(m[k].v[1], 0.2, 1e-3) << wall << " t = " << t[k];
      EXPECT_GT(m[k].x[0], 0.2 + 0.05 - 0.01) << wall << " t = " << t[k];
    }
    EXPECT_GT(m.back().v[0], 0.5) << wall << ": the block must come back off the wall";
  }
}

/// The context of this test's grid: 1.2 m x 0.8 m of 0.01 m cells, one ghost layer.
SolverContext grid_context() {
  SolverContext ctx;
  ctx.name = "plane";
  ctx.dimension = 2;
  ctx.cell_size = 0.01;
  ctx.domain_lower = {0, 0};
  ctx.domain_upper = {1.2, 0.8};
  ctx.grid_origin = {-0.01, -0.01};
  ctx.grid_nodes = {123, 83};
  return ctx;
}

/// The errors of `entries` as `plane { ... }` in constant/boundaryConditions: the spec's
/// validation, then the construction against the grid, as a run and --check do.
std::vector<std::string> errors_of(const std::string& entries) {
  const Dictionary file = Dictionary::parse("plane { " + entries + " }", "constant/boundaryConditions");
  const Dictionary& d = file.sub("plane");
  const PluginEntry* pe = runtime().registry().find(PluginKind::boundaryCondition, "inclinedPlane");
  if (!pe) return {"the inclinedPlane plugin is not loaded"};
  std::vector<InputError> errors;
  validate(*pe->spec, d, errors, 2);
  if (errors.empty()) {
    try {
      pe->boundary(d, grid_context());
    } catch (const InputError& e) {
      errors.push_back(e);
    }
  }
  std::vector<std::string> out;
  for (const InputError& e : errors) out.push_back(e.what());
  return out;
}

TEST(InclinedPlanePlugin, ActsOnTheNodesInReachAndHoldsTheNodesBehind) {
  const PluginEntry* pe = runtime().registry().find(PluginKind::boundaryCondition, "inclinedPlane");
  ASSERT_NE(pe, nullptr) << "the inclinedPlane plugin is not loaded";
  const SolverContext ctx = grid_context();
  const double h = ctx.cell_size, band = 1.5 * h * (kN[0] + kN[1]);  // 1.5 h |n|_1
  for (const std::string condition : {"condition friction; coefficient 0.3;", "condition noSlip;"}) {
    const Dictionary file = Dictionary::parse("plane { " + inclined_plane(condition) + " }", "boundaryConditions");
    WallSet set(NodeLattice::of(ctx));
    pe->boundary(file.sub("plane"), ctx)->constrain(set);
    const bool friction = condition.find("friction") != std::string::npos;
    ASSERT_EQ(set.table().size(), friction ? 2u : 1u) << condition;
    if (friction) {
      const Wall& w = set.table()[0];
      EXPECT_EQ(w.mode, Wall::Mode::contact);
      EXPECT_NEAR(w.normal[0], kN[0], 1e-12);
      EXPECT_NEAR(w.normal[1], kN[1], 1e-12);
      EXPECT_EQ(w.mu, 0.3);
      EXPECT_EQ(w.separable, 1);
      EXPECT_EQ(set.table()[1].mode, Wall::Mode::stick);
    } else {
      EXPECT_EQ(set.table()[0].mode, Wall::Mode::stick);
    }
    Index in_front = 0, cut = 0, inside = 0;
    for (int j = 0; j < ctx.grid_nodes[1]; ++j)
      for (int i = 0; i < ctx.grid_nodes[0]; ++i) {
        const double x = ctx.grid_origin[0] + h * i, y = ctx.grid_origin[1] + h * j;
        const double d = x * kN[0] + (y - 0.7) * kN[1];
        // On or behind the plane, the nodes a point in front of it reaches: it lies in the
        // support [x - 1.5 h, x + 1.5 h]^2 of a node (bspline2, the widest) iff d > -1.5 h |n|_1.
        const WallMask expected = d > 1e-9 ? 0u : (!friction || d > -band + 1e-9 ? 1u : 2u);
        const WallMask mask = set.masks()[static_cast<std::size_t>(j) * ctx.grid_nodes[0] + i];
        ASSERT_EQ(mask, expected) << condition << " node (" << x << ", " << y << "), d = " << d << " m";
        (d > 1e-9 ? in_front : d > -band + 1e-9 ? cut : inside)++;
      }
    EXPECT_GT(in_front, 0);
    EXPECT_GT(cut, 100);
    EXPECT_GT(inside, 1000);
  }
}

TEST(InclinedPlanePlugin, RejectsAZeroNormalAPlaneOffTheGridAndAMisusedCoefficient) {
  const std::string at = "^constant/boundaryConditions:1:";
  auto expect_one = [&](const std::string& entries, const std::string& pattern) {
    const std::vector<std::string> e = errors_of(entries);
    ASSERT_EQ(e.size(), 1u) << entries;
    EXPECT_TRUE(std::regex_search(e[0], std::regex(at + pattern))) << entries << "\n  " << e[0];
  };
  EXPECT_TRUE(errors_of(inclined_plane("condition slip;")).empty());
  expect_one("type inclinedPlane; point (0 0.7); normal (0 0); condition slip;",
             "[0-9]+: normal: must not be zero");
  expect_one(inclined_plane("condition friction; coefficient -0.2;"), "[0-9]+: coefficient: expected a number >= 0");
  expect_one(inclined_plane("condition friction;"), "[0-9]+: missing required entry 'coefficient' in 'plane'");
  expect_one(inclined_plane("condition slip; coefficient 0.2;"), "[0-9]+: coefficient: only condition friction");
  expect_one(inclined_plane("condition noSlip; separable no;"), "[0-9]+: separable: condition noSlip");
  expect_one("type inclinedPlane; point (0 -0.5); normal (0.5 0.866); condition slip;",
             "[0-9]+: point: the plane .* misses the grid: every node of the domain \\(0 0\\)-\\(1.2 0.8\\) lies in front");
  expect_one("type inclinedPlane; point (0 2); normal (0.5 0.866); condition slip;",
             "[0-9]+: point: the plane .* leaves no room: every node of the domain .* lies on or behind it");
}

}  // namespace
}  // namespace scree::test

SCREE_TEST_MAIN()
