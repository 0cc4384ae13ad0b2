// The geostatic initial stress from the material above each point (case/overburden.hpp,
// `overburden all`) against the weight of the layers above it,
//     sigma_v(x, z) = -g sum_i rho_i t_i(x, z),   sigma_h = K0 sigma_v   (tension positive),
// with t_i the thickness of layer i above the point. The material of a body is its sub-cells
// (side s = h/n) whose centres lie inside its region. Where a column's top is level with a
// sub-cell edge (a layer bounded by lattice lines) the column sum is the integral to
// round-off; where an inclined face cuts the column, the column's material ends at the edge
// of the highest sub-cell whose centre is inside, within s/2 of the face above the column's
// centre, so the column sum errs by at most rho g s/2 there.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "scree/case/case_model.hpp"
#include "scree/case/overburden.hpp"
#include "scree/case/particle_generation.hpp"
#include "scree_test.hpp"

namespace scree::test {
namespace {

constexpr double kG = 9.81;
constexpr double kK0 = 0.5;

GridGeometry<2> grid2(double h) {
  GridSettings gs;
  gs.dimension = 2;
  gs.lower = {0, 0, 0};
  gs.upper = {6, 4, 0};
  gs.cell_size = h;
  gs.ghost_layers = 2;
  return grid_geometry<2>(gs);
}

Vec<2> down2() {
  Vec<2> g;
  g[0] = 0;
  g[1] = -kG;
  return g;
}

Dictionary bodies(const std::string& text) { return Dictionary::parse(text, "constant/bodies"); }

// ---- a layered slope in 2D ----------------------------------------------------------------
//
// A base layer 1 m thick (rho_b = 2000) across the domain, and on it a slope drawn as one
// polygon (rho_s = 1800): 2 m high, crest from x = 0 to 2.02, a 45 degree face down to the
// toe at x = 4.02 (the face x + y = 5.02 passes between the sub-cell centres, which sit at
// multiples of 0.05 plus 0.025). Analytic overburden at (x, y):
//   in the slope:     sigma_v = -g rho_s (top(x) - y),  top(x) = min(3, 5.02 - x)
//   in the base:      sigma_v = -g (rho_b (1 - y) + rho_s max(0, top(x) - 1))
constexpr double kRhoBase = 2000, kRhoSlope = 1800, kH = 0.1;
constexpr int kPpc = 2;
constexpr double kSub = kH / kPpc;
const char* kLayers =
    "base { material b; particlesPerCell 2; region { type rectangle; lower (0 0); upper (6 1); } "
    "initialStress { type geostatic; K0 0.5; } } "
    "slope { material s; particlesPerCell 2; region { type polygon; points ((0 1) (4.02 1) (2.02 3) (0 3)); } "
    "initialStress { type geostatic; K0 0.5; } }";

double slope_top(double x) { return std::min(3.0, 5.02 - x); }

double analytic_sv(double x, double y, bool in_base) {
  const double above_base = std::max(0.0, slope_top(x) - 1);
  return in_base ? -kG * (kRhoBase * (1 - y) + kRhoSlope * above_base) : -kG * kRhoSlope * (slope_top(x) - y);
}

/// Where the face cuts the point's column (the column's centre, the point's x, within s/2
/// of the face's height 5.02 - x below the crest's level), the column sum's bound
/// rho_s g s/2; else round-off of the stress (1e-9 of the largest, 7e4 Pa).
double tolerance(double x) {
  const bool cut = x > 2.02 - kSub / 2 && x < 4.02 + kSub / 2;
  return cut ? kRhoSlope * kG * kSub / 2 + 1e-9 * 7e4 : 1e-9 * 7e4;
}

struct Measured {
  double worst_crest = 0, worst_face = 0, worst_toe = 0;
  int crest = 0, face = 0, toe = 0;
};

void expect_layers(const GeneratedParticles<2>& b, bool in_base, Measured& m) {
  ASSERT_FALSE(b.x.empty());
  for (std::size_t p = 0; p < b.x.size(); ++p) {
    const double x = b.x[p][0], y = b.x[p][1], sv = analytic_sv(x, y, in_base);
    ASSERT_NEAR(b.sigma[p][1], sv, tolerance(x)) << (in_base ? "base" : "slope") << " at (" << x << " " << y << ")";
    ASSERT_NEAR(b.sigma[p][0], kK0 * b.sigma[p][1], 1e-12 * 7e4);
    ASSERT_NEAR(b.sigma[p][2], kK0 * b.sigma[p][1], 1e-12 * 7e4);
    ASSERT_EQ(b.sigma[p][3], 0);
    const double err = std::fabs(b.sigma[p][1] - sv);
    if (x < 2.02) m.worst_crest = std::max(m.worst_crest, err), ++m.crest;
    else if (x < 4.02) m.worst_face = std::max(m.worst_face, err), ++m.face;
    else m.worst_toe = std::max(m.worst_toe, err), ++m.toe;
  }
}

TEST(Overburden, LayeredSlopeCarriesTheLayersAboveEachPoint) {
  const Dictionary d = bodies(kLayers);
  const GridGeometry<2> g = grid2(kH);
  Overburden<2> ob(down2());
  ob.add_body(d.sub("base"), g, DensityProfile{kRhoBase, {}});
  ob.add_body(d.sub("slope"), g, DensityProfile{kRhoSlope, {}});
  Measured m;
  expect_layers(generate_particles<2>(d.sub("base"), g, kRhoBase, down2(), {}, {}, &ob), true, m);
  expect_layers(generate_particles<2>(d.sub("slope"), g, kRhoSlope, down2(), {}, {}, &ob), false, m);
  EXPECT_GT(m.crest, 0);
  EXPECT_GT(m.face, 0);
  EXPECT_GT(m.toe, 0);
  std::printf("largest |sigma_v - analytic| [Pa]: under the crest %.3g, under the face %.3g (bound %.3g), at the "
              "toe %.3g\n",
              m.worst_crest, m.worst_face, kRhoSlope * kG * kSub / 2, m.worst_toe);
  // The points named: under the crest at the base's bottom, under the face, at the toe.
  const Vec<2> crest{{0.025, 0.025}}, face{{3.025, 0.525}}, toe{{5.025, 0.025}};
  EXPECT_NEAR(ob.vertical_stress(crest), analytic_sv(0.025, 0.025, true), tolerance(0.025));
  EXPECT_NEAR(ob.vertical_stress(face), analytic_sv(3.025, 0.525, true), tolerance(3.025));
  EXPECT_NEAR(ob.vertical_stress(toe), analytic_sv(5.025, 0.025, true), tolerance(5.025));
}

// The slope alone, drawn as one polygon, with the default keys: each point carries the soil
// of its own column, not the crest's (its toe at x = 3.925 is 0.1 m deep, not 2 m).
TEST(Overburden, OnePolygonSlopeAloneLoadsItsToeWithItsOwnColumn) {
  const Dictionary d = bodies(kLayers);
  const GridGeometry<2> g = grid2(kH);
  const GeneratedParticles<2> b = generate_particles<2>(d.sub("slope"), g, kRhoSlope, down2());
  double worst = 0;
  for (std::size_t p = 0; p < b.x.size(); ++p) {
    const double x = b.x[p][0], y = b.x[p][1], sv = -kG * kRhoSlope * (slope_top(x) - y);
    ASSERT_NEAR(b.sigma[p][1], sv, tolerance(x)) << "at (" << x << " " << y << ")";
    worst = std::max(worst, std::fabs(b.sigma[p][1] - sv));
  }
  std::printf("one polygon: largest |sigma_v - analytic| %.3g Pa (bound %.3g)\n", worst, kRhoSlope * kG * kSub / 2);
}

// Every rank walks every body's whole lattice: cut into three slabs across x, each slab's
// points carry the stress the whole body's have, bit for bit.
TEST(Overburden, ARanksPartHasTheWholeBodysStressBitForBit) {
  const Dictionary d = bodies(kLayers);
  const GridGeometry<2> g = grid2(kH);
  Overburden<2> ob(down2());
  ob.add_body(d.sub("base"), g, DensityProfile{kRhoBase, {}});
  ob.add_body(d.sub("slope"), g, DensityProfile{kRhoSlope, {}});
  const auto whole = generate_particles<2>(d.sub("base"), g, kRhoBase, down2(), {}, {}, &ob);
  const double cuts[4] = {-1e9, 2.0, 3.5, 1e9};
  std::size_t seen = 0;
  for (int r = 0; r < 3; ++r) {
    Overburden<2> own(down2());  // built again, as each rank does
    own.add_body(d.sub("base"), g, DensityProfile{kRhoBase, {}});
    own.add_body(d.sub("slope"), g, DensityProfile{kRhoSlope, {}});
    const PointFilter<2> mine = [&](const Vec<2>& x) { return x[0] >= cuts[r] && x[0] < cuts[r + 1]; };
    const auto part = generate_particles<2>(d.sub("base"), g, kRhoBase, down2(), {}, mine, &own);
    for (std::size_t k = 0; k < part.x.size(); ++k) {
      const auto p = static_cast<std::size_t>(part.index[k]);
      for (int c = 0; c < 6; ++c) ASSERT_EQ(part.sigma[k][c], whole.sigma[p][c]);
    }
    seen += part.x.size();
  }
  EXPECT_EQ(seen, whole.x.size());
}

// A body with a gap in its columns (a C open to the right: material at 0 <= y <= 0.3 and
// 0.7 <= y <= 1 for x > 0.3, full height for x < 0.3): below the gap a point carries the
// roof's 0.3 m as well as the soil above it (the column's weight; no arching across the gap),
// sigma_v = -rho g ((0.3 - y) + 0.3). Faces on sub-cell edges: round-off.
TEST(Overburden, APointBelowAGapCarriesTheRoofAbove) {
  const Dictionary d = bodies("c { material m; region { type polygon; points ((0 0) (1 0) (1 0.3) (0.3 0.3) (0.3 0.7) "
                              "(1 0.7) (1 1) (0 1)); } initialStress { type geostatic; K0 0.5; } }");
  const auto b = generate_particles<2>(d.sub("c"), grid2(0.1), 2000, down2());
  int below_gap = 0;
  for (std::size_t p = 0; p < b.x.size(); ++p) {
    const double x = b.x[p][0], y = b.x[p][1];
    const double t = x < 0.3 ? 1 - y : (y < 0.3 ? (0.3 - y) + 0.3 : 1 - y);
    ASSERT_NEAR(b.sigma[p][1], -2000 * kG * t, 1e-9 * 2e4) << "at (" << x << " " << y << ")";
    below_gap += x > 0.3 && y < 0.3;
  }
  EXPECT_GT(below_gap, 0);
}

// ---- a body standing alone with a level top: overburden body's stress, bit for bit ------
//
// sigma_v = -rho g (s - y) with s the top particle plus half a spacing: `overburden all` (the
// default) and `overburden body` (one level per body) give the same bits, for a top on a
// sub-cell edge and one inside a sub-cell (upper 0.98: top point 0.975, s = 1.0).
TEST(Overburden, ALevelBodyAloneHasTheFormerStressBitForBit) {
  for (const char* upper : {"(0.4 1)", "(0.4 0.98)"}) {
    const std::string region = std::string("region { type rectangle; lower (0.2 0.1); upper ") + upper + "; }";
    const Dictionary d = bodies("a { material m; " + region + " initialStress { type geostatic; K0 0.4; } } " +
                                "b { material m; " + region + " initialStress { type geostatic; K0 0.4; "
                                "overburden body; } }");
    const GridGeometry<2> g = grid2(0.04);
    const auto a = generate_particles<2>(d.sub("a"), g, 1900, down2());
    const auto b = generate_particles<2>(d.sub("b"), g, 1900, down2());
    ASSERT_EQ(a.x.size(), b.x.size());
    double top = -1;
    for (const auto& x : a.x) top = std::max(top, static_cast<double>(x[1]));
    for (std::size_t p = 0; p < a.x.size(); ++p) {
      for (int c = 0; c < 6; ++c) ASSERT_EQ(a.sigma[p][c], b.sigma[p][c]) << upper << " point " << p;
      // Against rho g depth below the top point plus half a spacing (0.01 m), to round-off.
      ASSERT_NEAR(a.sigma[p][1], -1900 * kG * (top + 0.01 - a.x[p][1]), 1e-9 * 1900 * kG);
    }
  }
}

// ---- 3D: a stack of two boxes under gravity along -z -------------------------------------
//
// A lower box (0..1, 0..1, 0..0.5) of rho 2000 carries an upper box (0..0.6, 0..1, 0.5..1) of
// rho 1500: below the upper box sigma_zz = -g (1500 0.5 + 2000 (0.5 - z)), beside it
// -g 2000 (0.5 - z). Both boxes' faces lie on sub-cell edges: round-off only.
TEST(Overburden, StackOfBoxesIn3DUnderGravityAlongZ) {
  GridSettings gs;
  gs.dimension = 3;
  gs.lower = {0, 0, 0};
  gs.upper = {1, 1, 1.2};
  gs.cell_size = 0.1;
  gs.ghost_layers = 2;
  const GridGeometry<3> g = grid_geometry<3>(gs);
  Vec<3> down;
  down[0] = 0;
  down[1] = 0;
  down[2] = -kG;
  const Dictionary d = bodies(
      "low { material a; region { type box; lower (0 0 0); upper (1 1 0.5); } initialStress { type geostatic; "
      "K0 0.4; } } "
      "high { material b; region { type box; lower (0 0 0.5); upper (0.6 1 1); } initialStress { type geostatic; "
      "K0 0.4; } }");
  Overburden<3> ob(down);
  ob.add_body(d.sub("low"), g, DensityProfile{2000, {}});
  ob.add_body(d.sub("high"), g, DensityProfile{1500, {}});
  const auto low = generate_particles<3>(d.sub("low"), g, 2000, down, {}, {}, &ob);
  const auto high = generate_particles<3>(d.sub("high"), g, 1500, down, {}, {}, &ob);
  const double tol = 1e-9 * 2e4;
  int under = 0, beside = 0;
  for (std::size_t p = 0; p < low.x.size(); ++p) {
    const double x = low.x[p][0], z = low.x[p][2];
    const double sv = -kG * ((x < 0.6 ? 1500 * 0.5 : 0) + 2000 * (0.5 - z));
    ASSERT_NEAR(low.sigma[p][2], sv, tol) << "low at x " << x << " z " << z;
    ASSERT_NEAR(low.sigma[p][0], 0.4 * sv, tol);
    ASSERT_NEAR(low.sigma[p][1], 0.4 * sv, tol);
    (x < 0.6 ? under : beside)++;
  }
  for (std::size_t p = 0; p < high.x.size(); ++p)
    ASSERT_NEAR(high.sigma[p][2], -kG * 1500 * (1 - high.x[p][2]), tol);
  EXPECT_GT(under, 0);
  EXPECT_GT(beside, 0);
}

// ---- 3D: a sphere, whose top is curved in both horizontal directions ---------------------
//
// A sphere of radius R = 0.3 about the origin, rho 1800, gravity along -z: the material above
// (x, y, z) is the sphere's cap, sqrt(R^2 - x^2 - y^2) - z thick, so sigma_zz = -rho g
// (sqrt(R^2 - x^2 - y^2) - z), with the column sum within rho g s/2 of it where the sphere's
// surface crosses the column (s = 0.02 m: 177 Pa), plus round-off. The rule `overburden body` (one level,
// the sphere's top) would load a point near the equator with the whole cap above the equator's
// level, up to rho g R = 5.3 kPa more.
TEST(Overburden, SphereIn3DCarriesItsCapAboveEachPoint) {
  GridSettings gs;
  gs.dimension = 3;
  gs.lower = {-0.4, -0.4, -0.4};
  gs.upper = {0.4, 0.4, 0.4};
  gs.cell_size = 0.04;
  gs.ghost_layers = 2;
  const GridGeometry<3> g = grid_geometry<3>(gs);
  Vec<3> down;
  down[0] = 0;
  down[1] = 0;
  down[2] = -kG;
  const Dictionary d = bodies("ball { material a; region { type sphere; centre (0 0 0); radius 0.3; } "
                              "initialStress { type geostatic; K0 0.4; } }");
  const auto b = generate_particles<3>(d.sub("ball"), g, 1800, down);
  ASSERT_FALSE(b.x.empty());
  const double tol = 1800 * kG * 0.02 / 2 + 1e-9 * 1800 * kG * 0.6;
  double worst = 0;
  for (std::size_t p = 0; p < b.x.size(); ++p) {
    const double x = b.x[p][0], y = b.x[p][1], z = b.x[p][2];
    const double sv = -1800 * kG * (std::sqrt(0.09 - x * x - y * y) - z);
    ASSERT_NEAR(b.sigma[p][2], sv, tol) << "at (" << x << " " << y << " " << z << ")";
    ASSERT_NEAR(b.sigma[p][0], 0.4 * b.sigma[p][2], 1e-9 * 1e4);
    worst = std::max(worst, std::fabs(b.sigma[p][2] - sv));
  }
  std::printf("sphere: %zu points, largest |sigma_zz - analytic| %.3g Pa (bound %.3g)\n", b.x.size(), worst, tol);
}

// ---- gravity along x, either way --------------------------------------------------------
//
// Two rectangles side by side along x: a (1..2, rho 2000) and b (2..2.5, rho 1500), both
// 1 <= y <= 2. With g along -x, "up" is +x and b lies on a: sigma_xx = -g (1500 0.5 + 2000
// (2 - x)) in a, -g 1500 (2.5 - x) in b. With g along +x, up is -x and a lies on b:
// -g 2000 (x - 1) in a, -g (2000 1 + 1500 (x - 2)) in b. Faces on sub-cell edges: round-off.
TEST(Overburden, GravityAlongXEitherWay) {
  const Dictionary d = bodies("a { material m; region { type rectangle; lower (1 1); upper (2 2); } "
                              "initialStress { type geostatic; K0 0.5; } } "
                              "b { material m; region { type rectangle; lower (2 1); upper (2.5 2); } "
                              "initialStress { type geostatic; K0 0.5; } }");
  const GridGeometry<2> g = grid2(0.1);
  for (const double sign : {-1.0, 1.0}) {
    Vec<2> grav;
    grav[0] = sign * kG;
    grav[1] = 0;
    Overburden<2> ob(grav);
    ob.add_body(d.sub("a"), g, DensityProfile{2000, {}});
    ob.add_body(d.sub("b"), g, DensityProfile{1500, {}});
    const auto a = generate_particles<2>(d.sub("a"), g, 2000, grav, {}, {}, &ob);
    const auto b = generate_particles<2>(d.sub("b"), g, 1500, grav, {}, {}, &ob);
    const double tol = 1e-9 * 4e4;
    for (std::size_t p = 0; p < a.x.size(); ++p) {
      const double x = a.x[p][0];
      const double sv = sign < 0 ? -kG * (1500 * 0.5 + 2000 * (2 - x)) : -kG * 2000 * (x - 1);
      ASSERT_NEAR(a.sigma[p][0], sv, tol) << "a at x " << x << ", g along " << sign << " x";
      ASSERT_NEAR(a.sigma[p][1], 0.5 * sv, tol);
    }
    for (std::size_t p = 0; p < b.x.size(); ++p) {
      const double x = b.x[p][0];
      const double sv = sign < 0 ? -kG * 1500 * (2.5 - x) : -kG * (2000 * 1 + 1500 * (x - 2));
      ASSERT_NEAR(b.sigma[p][0], sv, tol) << "b at x " << x << ", g along " << sign << " x";
    }
  }
}

// ---- gravity off the axes -----------------------------------------------------------------
//
// The columns need gravity along one axis: `overburden all` says so at its file:line, and
// `overburden body` (one level, measured along g) still takes any direction.
TEST(Overburden, GravityOffTheAxesIsRefusedUnlessOneLevelIsAsked) {
  const Dictionary d = bodies(
      "a { material m; region { type rectangle; lower (0.2 0.2); upper (0.6 1); } initialStress { type geostatic; } }\n"
      "b { material m; region { type rectangle; lower (0.2 0.2); upper (0.6 1); } initialStress { type geostatic; "
      "overburden body; } }");
  Vec<2> tilted;
  tilted[0] = kG * std::sin(0.3);
  tilted[1] = -kG * std::cos(0.3);
  try {
    generate_particles<2>(d.sub("a"), grid2(0.1), 2000, tilted);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("constant/bodies:1:"), std::string::npos) << what;
    EXPECT_NE(what.find("gravity along one axis"), std::string::npos) << what;
    EXPECT_NE(what.find("overburden body"), std::string::npos) << what;
  }
  const auto b = generate_particles<2>(d.sub("b"), grid2(0.1), 2000, tilted);
  ASSERT_FALSE(b.x.empty());
  double deepest = 0;
  for (const auto& s : b.sigma) deepest = std::min(deepest, static_cast<double>(s[0] + s[1]));
  EXPECT_LT(deepest, 0);
}

}  // namespace
}  // namespace scree::test
