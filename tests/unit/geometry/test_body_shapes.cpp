// The regions of constant/bodies in 3D: cylinder, sphere, extrudedPolygon, stl and the
// body's clip box.
//
// Mass. A body's points sit at the centres of the sub-cells (side s = h / n) whose centres
// are inside the region, each with the sub-cell's volume, so its mass is rho V_h with V_h the
// volume of those sub-cells. Every point of a sub-cell lies within its half-diagonal
// delta = sqrt(3)/2 s of the centre. Where the centre is inside and part of the sub-cell
// outside, that part lies outside the region within delta of its surface (the segment from
// the centre crosses the surface); where the centre is outside, the part inside lies inside
// within delta. So V_h - V is at most the volume of the outer shell {x outside, dist(x, S) <=
// delta} and at least minus that of the inner shell; for a convex region the inner shell is
// the smaller (Steiner), hence
//     |V_h - V| <= V(region (+) ball(delta)) - V,
// which Steiner's formula gives for a convex polyhedron as A delta + (sum of edge lengths
// times exterior angle / 2) delta^2 + 4/3 pi delta^3 <= A delta + pi/2 L_edges delta^2 +
// 4/3 pi delta^3, for a sphere exactly, and a cylinder (r, L) lies with its shell inside the
// cylinder (r + delta, L + 2 delta). That bound, O(s / size), is each test's tolerance;
// where the region's faces are aligned with the sub-cells (a box), V_h = V to round-off, and
// the tolerance is that. The measured errors are printed: two orders of magnitude below the
// bound (the errors of cut sub-cells mostly cancel): sphere -0.008% (bound 5.3%), skew
// cylinder -0.07% (7.6%), extrudedPolygon +0.02% (3.0%), tetrahedron -0.03% (12.8%).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "scree/geometry/tri_surface.hpp"
#include "scree/case/particle_generation.hpp"
#include "scree/case/setup_check.hpp"
#include "scree_test.hpp"
#include "stl_surfaces.hpp"

namespace scree::test {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kRho = 1000;
constexpr double kH = 0.04;   // cell size
constexpr int kPpc = 4;       // points per cell along each axis
constexpr double kS = kH / kPpc;  // sub-cell side, 0.01
const double kDelta = std::sqrt(3.0) / 2 * kS;

/// The grid of the mass tests: (-1 -1 -1)..(1 1 1), cells of 0.04 m, 2 ghost layers (node 0
/// at -1.08, so sub-cell boundaries lie on multiples of 0.01).
GridGeometry<3> grid() {
  GridSettings gs;
  gs.dimension = 3;
  gs.lower = {-1, -1, -1};
  gs.upper = {1, 1, 1};
  gs.cell_size = kH;
  gs.ghost_layers = 2;
  return grid_geometry<3>(gs);
}

GeneratedParticles<3> generate(const std::string& body_entries, const std::filesystem::path& dir = {}) {
  const Dictionary d = Dictionary::parse("b { material soil; particlesPerCell " + std::to_string(kPpc) + "; " +
                                             body_entries + " }",
                                         "constant/bodies");
  Vec<3> g;
  g[0] = 0;
  g[1] = -9.81;
  g[2] = 0;
  return generate_particles<3>(d.sub("b"), grid(), kRho, g, dir);
}

double mass(const std::string& body_entries, const std::filesystem::path& dir = {}) {
  double m = 0;
  for (Real v : generate(body_entries, dir).volume) m += kRho * v;
  return m;
}

double estimate(const std::string& body_entries, const std::filesystem::path& dir = {}) {
  const Dictionary d = Dictionary::parse("b { material soil; " + body_entries + " }", "constant/bodies");
  return estimate_particle_count<3>(d.sub("b"), kH, kPpc, dir);
}

std::string vec(const P3& p) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.17g %.17g %.17g)", p[0], p[1], p[2]);
  return buf;
}

void expect_mass(const char* what, double m, double volume, double bound) {
  const double exact = kRho * volume;
  std::printf("%s: mass %.6g, rho V %.6g (%+.4f%%), bound %.4f%%\n", what, m, exact, 100 * (m / exact - 1),
              100 * bound / volume);
  EXPECT_NEAR(m, exact, kRho * bound) << what;
}

P3 minus(const P3& a, const P3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
P3 cross(const P3& a, const P3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double norm(const P3& a) { return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }

TEST(BodyMass, SphereIsRhoFourThirdsPiRCubed) {
  const double r = 0.5;
  const double V = 4.0 / 3 * kPi * r * r * r;
  const double bound = 4.0 / 3 * kPi * (std::pow(r + kDelta, 3) - r * r * r);
  expect_mass("sphere", mass("region { type sphere; centre (0.013 -0.021 0.007); radius 0.5; }"), V, bound);
}

TEST(BodyMass, CylinderOnASkewAxisIsRhoPiR2L) {
  // The axis from p1 to p2 along none of the grid's axes.
  const P3 p1{-0.3, -0.4, -0.2}, p2{0.35, 0.3, 0.25};
  const double r = 0.3, L = norm(minus(p2, p1));
  const double V = kPi * r * r * L;
  const double bound = kPi * (r + kDelta) * (r + kDelta) * (L + 2 * kDelta) - V;
  expect_mass("cylinder", mass("region { type cylinder; p1 " + vec(p1) + "; p2 " + vec(p2) + "; radius 0.3; }"), V,
              bound);
}

TEST(BodyMass, ExtrudedPolygonIsRhoAreaTimesLength) {
  // A convex pentagon in the (z x) plane extruded along y over -0.3..0.4, ends on sub-cell
  // boundaries: V_h = L A_h exactly, and A_h is within the 2D shell (perimeter P, delta2 =
  // sqrt(2)/2 s) of the pentagon's area: |A_h - A| <= P delta2 + pi delta2^2.
  const std::vector<std::array<double, 2>> zx = {{-0.5, -0.4}, {0.3, -0.5}, {0.6, 0.1}, {0.1, 0.55}, {-0.45, 0.3}};
  double twice = 0, P = 0;
  std::string pts;
  for (std::size_t i = 0, j = zx.size() - 1; i < zx.size(); j = i++) {
    twice += zx[j][0] * zx[i][1] - zx[i][0] * zx[j][1];
    P += std::hypot(zx[i][0] - zx[j][0], zx[i][1] - zx[j][1]);
    pts += " (" + std::to_string(zx[i][0]) + " " + std::to_string(zx[i][1]) + ")";
  }
  const double A = std::fabs(twice) / 2, L = 0.7, d2 = std::sqrt(2.0) / 2 * kS;
  expect_mass("extrudedPolygon (axis y)",
              mass("region { type extrudedPolygon; axis y; range (-0.3 0.4); points (" + pts + "); }"), A * L,
              L * (P * d2 + kPi * d2 * d2));
}

TEST(BodyMass, ExtrudedPolygonTakesItsPointsInTheAxesAfterItsAxis) {
  // The same right triangle (legs 0.4 along the first coordinate, 0.2 along the second)
  // extruded along each axis: its bounding box shows which axes the points are in.
  for (const char* axis : {"x", "y", "z"}) {
    const auto b = generate(std::string("region { type extrudedPolygon; axis ") + axis +
                            "; range (0 0.1); points ((0 0) (0.4 0) (0 0.2)); }");
    const int a = axis[0] - 'x', u = (a + 1) % 3, v = (a + 2) % 3;
    double hi[3] = {-1, -1, -1};
    for (const auto& x : b.x)
      for (int d = 0; d < 3; ++d) hi[d] = std::max(hi[d], static_cast<double>(x[d]));
    EXPECT_NEAR(hi[a], 0.1 - kS / 2, 1e-9) << axis;
    EXPECT_GT(hi[u], 0.35) << "axis " << axis << ": the first coordinate is axis " << u;
    EXPECT_LT(hi[v], 0.2) << "axis " << axis << ": the second coordinate is axis " << v;
    EXPECT_GT(hi[v], 0.15) << axis;
  }
}

TEST(BodyMass, StlBoxAlignedWithTheSubCellsIsExact) {
  // Faces on sub-cell boundaries: every sub-cell is inside or outside, V_h = V. The rays
  // from points with x = y run through the diagonals of the z faces (the fill rule's case).
  TempCase tc("stl_box");
  std::filesystem::create_directories(tc.dir() / "constant/triSurface");
  const auto tris = box({-0.3, -0.2, -0.1}, {0.5, 0.4, 0.3});
  write_ascii_stl((tc.dir() / "constant/triSurface/box.stl").string(), tris);
  write_binary_stl((tc.dir() / "constant/triSurface/box_binary.stl").string(), tris);
  const double V = 0.8 * 0.6 * 0.4;
  expect_mass("stl box (ASCII)", mass("region { type stl; file \"constant/triSurface/box.stl\"; }", tc.dir()), V,
              1e-9 * V);
  expect_mass("stl box (binary)",
              mass("region { type stl; file \"constant/triSurface/box_binary.stl\"; }", tc.dir()), V, 1e-9 * V);
}

TEST(BodyMass, StlLShapedPrismIsExact) {
  // A concave surface: an L (three 0.2 m squares) extruded along z, its caps fans from the
  // reflex corner. Rays cross it up to four times. Faces on sub-cell boundaries: exact.
  const double a = 0.2, z0 = -0.3, z1 = 0.2, x0 = -0.2, y0 = -0.1;
  const std::vector<std::array<double, 2>> L = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
  auto at = [&](const std::array<double, 2>& p, double z) { return P3{x0 + a * p[0], y0 + a * p[1], z}; };
  std::vector<Tri> tris;
  for (std::size_t i = 0; i < L.size(); ++i) {  // the sides, outward for the counter-clockwise L
    const auto& p = L[i];
    const auto& q = L[(i + 1) % L.size()];
    tris.push_back({at(p, z0), at(q, z0), at(q, z1)});
    tris.push_back({at(p, z0), at(q, z1), at(p, z1)});
  }
  for (std::size_t i = 4; i < L.size() + 2; ++i) {  // the caps: fans from the reflex corner L[3]
    const auto& p = L[i % L.size()];
    const auto& q = L[(i + 1) % L.size()];
    tris.push_back({at(L[3], z1), at(p, z1), at(q, z1)});
    tris.push_back({at(L[3], z0), at(q, z0), at(p, z0)});
  }
  TempCase tc("stl_L");
  std::filesystem::create_directories(tc.dir() / "constant/triSurface");
  write_ascii_stl((tc.dir() / "constant/triSurface/L.stl").string(), tris);
  const double V = 3 * a * a * (z1 - z0);
  expect_mass("stl L-shaped prism", mass("region { type stl; file \"constant/triSurface/L.stl\"; }", tc.dir()), V,
              1e-9 * V);
  auto s = geometry::TriSurface::load(tc.dir() / "constant/triSurface/L.stl", "L.stl", SourceLocation{});
  EXPECT_NEAR(s->volume(), V, 1e-12);
  EXPECT_FALSE(s->contains({x0 + 1.5 * a, y0 + 1.5 * a, 0}));  // the notch
  EXPECT_TRUE(s->contains({x0 + 0.5 * a, y0 + 1.5 * a, 0}));
}

TEST(BodyMass, StlTetrahedronIsRhoDetOverSix) {
  TempCase tc("stl_tet");
  std::filesystem::create_directories(tc.dir() / "constant/triSurface");
  const P3 a{-0.5, -0.4, -0.3}, b{0.6, -0.2, -0.35}, c{0.1, 0.6, -0.25}, d{0.0, 0.05, 0.55};
  const P3 ab = minus(b, a), ac = minus(c, a), ad = minus(d, a);
  const P3 n = cross(ab, ac);
  const double det = n[0] * ad[0] + n[1] * ad[1] + n[2] * ad[2];
  ASSERT_GT(det, 0);
  const double V = det / 6;
  double area = 0, edges = 0;
  for (const auto& t : tetrahedron(a, b, c, d)) area += norm(cross(minus(t[1], t[0]), minus(t[2], t[0]))) / 2;
  for (const auto& [p, q] : {std::pair{a, b}, {a, c}, {a, d}, {b, c}, {b, d}, {c, d}}) edges += norm(minus(q, p));
  const double bound = area * kDelta + kPi / 2 * edges * kDelta * kDelta + 4.0 / 3 * kPi * std::pow(kDelta, 3);
  write_ascii_stl((tc.dir() / "constant/triSurface/tet.stl").string(), tetrahedron(a, b, c, d));
  const std::string region = "region { type stl; file \"constant/triSurface/tet.stl\"; }";
  expect_mass("stl tetrahedron", mass(region, tc.dir()), V, bound);
  // The memory estimate's count: the divergence theorem's volume times (n / h)^3.
  EXPECT_NEAR(estimate(region, tc.dir()), V * std::pow(kPpc / kH, 3), 1e-9 * V * std::pow(kPpc / kH, 3));
}

TEST(BodyMass, ClippedQuarterCylinderIsAQuarterOfTheWhole) {
  // The axis on x = y = 0, a plane of sub-cell boundaries: the lattice is symmetric about
  // both planes the clip box cuts along, so the quarter holds exactly a quarter of the points
  // (no centre lies on the circle: (k + 1/2)^2 + (m + 1/2)^2 is never the integer 1600).
  const std::string cyl = "region { type cylinder; p1 (0 0 -0.5); p2 (0 0 0.5); radius 0.4; }";
  const double whole = mass(cyl), quarter = mass(cyl + " clip { lower (0 0 -1); upper (1 1 1); }");
  std::printf("whole cylinder %.6g, clipped quarter %.6g (x 4 = %.6g)\n", whole, quarter, 4 * quarter);
  EXPECT_NEAR(quarter, whole / 4, 1e-9 * whole);  // the same points; the sums round differently
  const double V = kPi * 0.4 * 0.4 * 1.0;
  expect_mass("quarter cylinder", quarter, V / 4, (kPi * std::pow(0.4 + kDelta, 2) * (1 + 2 * kDelta) - V) / 4);
}

TEST(BodyMass, MemoryEstimateCountsThePointsOfEachShape) {
  // estimate_particle_count: the exact volume times (n / h)^3, so within the mass bound of the
  // count; clipped, the share of 32^3 midpoints of the clipped bounds (a quarter disc on 32 x
  // 32 midpoints: within perimeter x sqrt(2)/2 (r / 32) of its area, 4.4%).
  const double per_volume = std::pow(kPpc / kH, 3);
  struct Case {
    std::string entries;
    double volume, rel_tol;
  } cases[] = {
      {"region { type sphere; centre (0 0 0); radius 0.5; }", 4.0 / 3 * kPi * 0.125, 0.06},
      {"region { type cylinder; p1 (0 0 -0.5); p2 (0 0 0.5); radius 0.4; }", kPi * 0.16, 0.06},
      {"region { type extrudedPolygon; range (0 0.5); points ((0 0) (0.4 0) (0 0.2)); }", 0.04 * 0.5, 0.06},
      {"region { type cylinder; p1 (0 0 -0.5); p2 (0 0 0.5); radius 0.4; } clip { lower (0 0 -1); upper (1 1 1); }",
       kPi * 0.16 / 4, 0.05},
  };
  for (const auto& c : cases) {
    const double n = static_cast<double>(generate(c.entries).x.size()), e = estimate(c.entries);
    std::printf("%s: %.0f points, estimated %.0f (%+.2f%%)\n", c.entries.c_str(), n, e, 100 * (e / n - 1));
    EXPECT_NEAR(e, c.volume * per_volume, c.rel_tol * c.volume * per_volume) << c.entries;
    EXPECT_NEAR(e, n, c.rel_tol * n) << c.entries;
  }
}

/// A surface triangle from the STL writer's vertices (stl_surfaces.hpp).
geometry::TriSurface::Triangle triangle(const P3& a, const P3& b, const P3& c) {
  auto p = [](const P3& q) { return geometry::Point3{{q[0], q[1], q[2]}}; };
  return {{p(a), p(b), p(c)}, 0};
}

TEST(StlInside, PointsOnTheMainDiagonalOfACube) {
  // x = y = z: each of the three rays runs through the diagonal edges of the two faces it
  // crosses, and through the cube's corners at the ends. Inside strictly between them.
  auto s = geometry::TriSurface::from_triangles(
      [] {
        std::vector<geometry::TriSurface::Triangle> t;
        for (const auto& tri : box({0, 0, 0}, {1, 1, 1})) t.push_back(triangle(tri[0], tri[1], tri[2]));
        return t;
      }(),
      "cube", SourceLocation{});
  for (double x : {0.05, 0.25, 0.5, 0.75, 0.95}) EXPECT_TRUE(s->contains({x, x, x})) << x;
  for (double x : {-0.25, 1.25}) EXPECT_FALSE(s->contains({x, x, x})) << x;
  // Beside the cube, in line with an edge in every projection.
  EXPECT_FALSE(s->contains({1.5, 0.5, 0.5}));
  EXPECT_FALSE(s->contains({0.5, -0.5, 0.5}));
  EXPECT_DOUBLE_EQ(s->volume(), 1.0);
}

TEST(StlInside, TrianglesOrientedEitherWayEncloseTheSameVolume) {
  // Half the faces of a cube turned inside out: the inside test does not use the normals,
  // and the volume (the memory estimate's) falls back to sampling: 1 within the share of
  // 48^3 midpoints a cube aligned with them gives exactly.
  std::vector<geometry::TriSurface::Triangle> t;
  int k = 0;
  for (const auto& tri : box({0, 0, 0}, {1, 1, 1})) {
    if (k++ % 4 < 2)
      t.push_back(triangle(tri[0], tri[1], tri[2]));
    else
      t.push_back(triangle(tri[0], tri[2], tri[1]));
  }
  auto s = geometry::TriSurface::from_triangles(t, "cube", SourceLocation{});
  EXPECT_TRUE(s->contains({0.3, 0.6, 0.2}));
  EXPECT_FALSE(s->contains({1.3, 0.6, 0.2}));
  EXPECT_NEAR(s->volume(), 1.0, 1e-12);
}

// ---- geostatic initial stress in 3D --------------------------------------------------

/// sigma_yy = -rho g (H - y), sigma_xx = sigma_zz = K0 sigma_yy, no shear, at every point of
/// a body whose top is the level y = H.
void expect_geostatic(const std::string& region, double H) {
  const double K0 = 0.4;
  const auto b = generate(region + " initialStress { type geostatic; K0 0.4; }");
  ASSERT_FALSE(b.x.empty());
  double deepest = 0;
  for (std::size_t p = 0; p < b.x.size(); ++p) {
    const double y = b.x[p][1], syy = -kRho * 9.81 * (H - y), tol = 1e-9 * kRho * 9.81;
    EXPECT_NEAR(b.sigma[p][1], syy, tol) << region << " at y = " << y;
    EXPECT_NEAR(b.sigma[p][0], K0 * syy, tol);
    EXPECT_NEAR(b.sigma[p][2], K0 * syy, tol);
    for (int k = 3; k < 6; ++k) EXPECT_NEAR(b.sigma[p][k], 0, tol);
    deepest = std::min(deepest, static_cast<double>(b.sigma[p][1]));
  }
  std::printf("%s: sigma_yy at the deepest point %.1f Pa\n", region.c_str(), deepest);
}

TEST(Geostatic3D, BoxHasRhoGDepthVerticallyAndK0TimesThatAcross) {
  expect_geostatic("region { type box; lower (-0.2 -0.5 -0.2); upper (0.2 0.1 0.2); }", 0.1);
}

TEST(Geostatic3D, UprightCylinderHasRhoGDepthVerticallyAndK0TimesThatAcross) {
  expect_geostatic("region { type cylinder; p1 (0 -0.5 0); p2 (0 0.1 0); radius 0.3; }", 0.1);
}

// ---- a rank's part of a body ------------------------------------------------------------
//
// A rank of a decomposed run makes only the points of its box (generate_particles with a
// filter). Whatever depends on the whole body must not depend on the filter: the geostatic
// surface (the body's top), a rotation's centre (its centroid), the order and so the ids.
// Cut into three slabs across x, a sphere turning about its centroid under its geostatic
// stress: the parts, put together in the order of their places, are the whole body's
// points bit for bit, and each part's total is the whole body's count.
TEST(RankPart, ThePartsOfThreeSlabsAreTheWholeBodysPointsBitForBit) {
  const std::string body = "region { type sphere; centre (0.1 -0.2 0.05); radius 0.3; } angularVelocity (0 0 2); "
                           "initialStress { type geostatic; K0 0.5; }";
  const GeneratedParticles<3> whole = generate(body);
  const Dictionary d = Dictionary::parse("b { material soil; particlesPerCell " + std::to_string(kPpc) + "; " + body +
                                             " }",
                                         "constant/bodies");
  Vec<3> g;
  g[0] = 0;
  g[1] = -9.81;
  g[2] = 0;
  const double cuts[4] = {-1e9, 0.0, 0.2, 1e9};
  std::vector<int> seen(whole.x.size(), 0);
  for (int r = 0; r < 3; ++r) {
    const PointFilter<3> mine = [&](const Vec<3>& x) { return x[0] >= cuts[r] && x[0] < cuts[r + 1]; };
    const GeneratedParticles<3> part = generate_particles<3>(d.sub("b"), grid(), kRho, g, {}, mine);
    EXPECT_EQ(part.total, whole.x.size());
    ASSERT_EQ(part.index.size(), part.x.size());
    EXPECT_GT(part.x.size(), 0u) << r;
    for (std::size_t k = 0; k < part.x.size(); ++k) {
      const std::size_t p = static_cast<std::size_t>(part.index[k]);
      ASSERT_LT(p, whole.x.size());
      ++seen[p];
      for (int a = 0; a < 3; ++a) {
        EXPECT_EQ(part.x[k][a], whole.x[p][a]);
        EXPECT_EQ(part.v[k][a], whole.v[p][a]);
      }
      for (int c = 0; c < 6; ++c) EXPECT_EQ(part.sigma[k][c], whole.sigma[p][c]);
      EXPECT_EQ(part.volume[k], whole.volume[p]);
      if (k > 0) EXPECT_LT(part.index[k - 1], part.index[k]);  // in the whole body's order
    }
  }
  for (std::size_t p = 0; p < seen.size(); ++p) ASSERT_EQ(seen[p], 1) << "point " << p;
  EXPECT_TRUE(whole.index.empty());  // without a filter every point is kept, in order
}

// ---- errors: file:line and key, before anything runs -----------------------------------

void write_case(const TempCase& tc, int dim, const std::string& region_line, const std::string& extra = "") {
  tc.write("system/controlDict", "endTime 0.01;\ndeltaT 1e-3;\nwriteInterval 0.005;\n");
  tc.write("system/gridDict", dim == 3 ? "dimension 3;\nlower (-1 -1 -1);\nupper (1 1 1);\ncellSize 0.1;\n"
                                       : "dimension 2;\nlower (-1 -1);\nupper (1 1);\ncellSize 0.1;\n");
  tc.write("constant/g", dim == 3 ? "value (0 -9.81 0);\n" : "value (0 -9.81);\n");
  tc.write("constant/materialProperties", "soil { type linearElastic; E 1e6; nu 0.3; rho 1000; }\n");
  // region on line 4
  tc.write("constant/bodies", "b\n{\n    material soil;\n    " + region_line + "\n" + extra + "}\n");
  tc.write("constant/boundaryConditions", "floor { type fixed; face yMin; }\n");
}

/// Every error Case::read and check_setup (what scree --check runs) report, one a line.
std::string errors_of(const TempCase& tc) {
  std::string out;
  try {
    const Case c = Case::read(tc.dir(), runtime());
    for (const auto& e : check_setup(c, runtime(), false).errors) out += std::string(e.what()) + "\n";
  } catch (const InputErrors& e) {
    out = e.what();
  } catch (const InputError& e) {
    out = e.what();
  }
  return out;
}

void expect_error(int dim, const std::string& region, const std::string& expected, const std::string& extra = "",
                  const std::function<void(const TempCase&)>& prepare = {}) {
  TempCase tc("shape_error");
  write_case(tc, dim, region, extra);
  if (prepare) prepare(tc);
  const std::string e = errors_of(tc);
  EXPECT_NE(e.find(expected), std::string::npos) << "expected: " << expected << "\nfound:\n" << e;
}

TEST(ShapeErrors, AValid3DCaseOfEachShapeChecksClean) {
  for (const char* r : {"region { type sphere; centre (0 0 0); radius 0.3; }",
                        "region { type cylinder; p1 (0 -0.5 0); p2 (0 0 0); radius 0.3; }",
                        "region { type extrudedPolygon; points ((0 0) (0.5 0) (0 0.5)); range (-0.2 0.2); }"}) {
    TempCase tc("shape_valid");
    write_case(tc, 3, r);
    EXPECT_EQ(errors_of(tc), "") << r;
  }
}

TEST(ShapeErrors, RadiusNotPositive) {
  expect_error(3, "region { type sphere; centre (0 0 0); radius 0; }", "constant/bodies:4:");
  expect_error(3, "region { type sphere; centre (0 0 0); radius 0; }", "radius: expected a number > 0");
  expect_error(3, "region { type cylinder; p1 (0 0 0); p2 (0 1 0); radius -1; }", "radius: expected a number > 0");
}

TEST(ShapeErrors, CylinderWithP1EqualToP2) {
  expect_error(3, "region { type cylinder; p1 (0 0.1 0); p2 (0 0.1 0); radius 0.2; }",
               "constant/bodies:4:43: p2: equals p1, so the cylinder has no axis");
}

TEST(ShapeErrors, ExtrudedPolygonRangeAndVertices) {
  expect_error(3, "region { type extrudedPolygon; points ((0 0) (1 0) (0 1)); range (0.5 0.5); }",
               "range: expected (min max) with min < max, found (0.5 0.5)");
  expect_error(3, "region { type extrudedPolygon; points ((0 0) (1 0) (0 1)); range (0.5 0.2); }",
               "range: expected (min max) with min < max");
  expect_error(3, "region { type extrudedPolygon; points ((0 0) (1 0)); range (0 0.2); }",
               "constant/bodies:4:36: points: a polygon needs at least 3 vertices, found 2");
}

TEST(ShapeErrors, AShapeOfTheOtherDimension) {
  expect_error(2, "region { type sphere; centre (0 0 0); radius 0.3; }",
               "constant/bodies:4:14: type: region type sphere does not fit a 2D case; expected rectangle or polygon");
  expect_error(2, "region { type stl; file \"a.stl\"; }", "region type stl does not fit a 2D case");
  expect_error(3, "region { type rectangle; lower (0 0 0); upper (0.5 0.5 0.5); }",
               "type: region type rectangle does not fit a 3D case; expected box, cylinder, sphere");
  expect_error(3, "region { type polygon; points ((0 0) (1 0) (0 1)); }",
               "region type polygon does not fit a 3D case");
}

TEST(ShapeErrors, AKeyOfAnotherType) {
  expect_error(3, "region { type cylinder; p1 (0 0 0); p2 (0 1 0); radius 0.1; lower (0 0 0); }",
               "constant/bodies:4:65: lower: not a key of a region of type cylinder; it takes p1, p2, radius");
}

TEST(ShapeErrors, AClipBoxThatMissesTheRegion) {
  expect_error(3, "region { type sphere; centre (0 0 0); radius 0.3; }",
               "constant/bodies:5:5: clip: the box (0.5 0.5 0.5) .. (0.9 0.9 0.9) does not meet the region",
               "    clip { lower (0.5 0.5 0.5); upper (0.9 0.9 0.9); }\n");
  // Meets the bounding box but not the sphere: no particle position.
  expect_error(3, "region { type sphere; centre (0 0 0); radius 0.3; }",
               "region: no particle position lies inside it", "    clip { lower (0.25 0.25 0.25); upper (0.9 0.9 0.9); }\n");
}

void write_file(const TempCase& tc, const std::string& rel, const std::string& text) {
  std::filesystem::create_directories((tc.dir() / rel).parent_path());
  tc.write(rel, text);
}

TEST(ShapeErrors, StlFileMissingMalformedOpenOrDegenerate) {
  const std::string r = "region { type stl; file \"constant/triSurface/s.stl\"; }";
  expect_error(3, r, "constant/bodies:4:24: file: constant/triSurface/s.stl does not exist");
  expect_error(3, r, "constant/triSurface/s.stl:5:1: malformed ASCII STL: expected 'vertex x y z' (vertex 2 of the "
                     "facet at line 2), found 'vertx 1 0 0'",
               "", [](const TempCase& tc) {
                 write_file(tc, "constant/triSurface/s.stl",
                            "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertx 1 0 0\nvertex 0 1 0\n"
                            "endloop\nendfacet\nendsolid s\n");
               });
  expect_error(3, r, "expected 'endsolid'", "", [](const TempCase& tc) {
    write_file(tc, "constant/triSurface/s.stl", "solid s\n");
  });
  expect_error(3, r, "constant/bodies:4:24: file: constant/triSurface/s.stl is neither an ASCII STL", "",
               [](const TempCase& tc) { write_file(tc, "constant/triSurface/s.stl", "not an stl\n"); });
  // A box with one triangle missing: its 3 edges are used once.
  expect_error(3, r,
               "constant/bodies:4:24: file: the surface of constant/triSurface/s.stl is not closed: 3 of its 18 edges "
               "are not shared by exactly two triangles",
               "", [](const TempCase& tc) {
                 auto t = box({-0.2, -0.2, -0.2}, {0.2, 0.2, 0.2});
                 t.pop_back();
                 std::filesystem::create_directories(tc.dir() / "constant/triSurface");
                 write_ascii_stl((tc.dir() / "constant/triSurface/s.stl").string(), t);
               });
  expect_error(3, r, "1 zero-area triangle(s) (the first: the facet at constant/triSurface/s.stl:86)", "",
               [](const TempCase& tc) {
                 auto t = box({-0.2, -0.2, -0.2}, {0.2, 0.2, 0.2});
                 t.push_back({P3{0, 0, 0}, P3{0.1, 0, 0}, P3{0.2, 0, 0}});
                 std::filesystem::create_directories(tc.dir() / "constant/triSurface");
                 write_ascii_stl((tc.dir() / "constant/triSurface/s.stl").string(), t);
               });
  // Binary, open: named by triangle.
  expect_error(3, r, "of triangle 1 of constant/triSurface/s.stl", "", [](const TempCase& tc) {
    auto t = box({-0.2, -0.2, -0.2}, {0.2, 0.2, 0.2});
    t.erase(t.begin() + 1);
    std::filesystem::create_directories(tc.dir() / "constant/triSurface");
    write_binary_stl((tc.dir() / "constant/triSurface/s.stl").string(), t);
  });
}

/// Writes `tris` as constant/triSurface/s.stl of `tc` (ASCII).
void write_stl(const TempCase& tc, const std::vector<Tri>& tris) {
  std::filesystem::create_directories(tc.dir() / "constant/triSurface");
  write_ascii_stl((tc.dir() / "constant/triSurface/s.stl").string(), tris);
}

// Two closed shells that overlap: the parity rule leaves their common part
// empty (2,560 points where the union has 3,280), so the file is an error naming both
// facets. The cubes cross exactly through the diagonals of each other's faces.
TEST(ShapeErrors, StlOfTwoOverlappingShellsIsRefused) {
  const std::string r = "region { type stl; file \"constant/triSurface/s.stl\"; }";
  expect_error(3, r,
               "constant/bodies:4:24: file: the surface of constant/triSurface/s.stl crosses itself: the facet at "
               "constant/triSurface/s.stl:",
               "", [](const TempCase& tc) {
                 auto t = box({0, 0, 0}, {0.2, 0.2, 0.2});
                 const auto b = box({0.1, 0.1, 0.1}, {0.3, 0.3, 0.3});
                 t.insert(t.end(), b.begin(), b.end());
                 write_stl(tc, t);
               });
  expect_error(3, r, "of two of its 2 closed shells, which overlap", "", [](const TempCase& tc) {
    auto t = box({0, 0, 0}, {0.2, 0.2, 0.2});
    const auto b = box({0.1, 0.1, 0.1}, {0.3, 0.3, 0.3});
    t.insert(t.end(), b.begin(), b.end());
    write_stl(tc, t);
  });
  // Crossing like a plus sign: no vertex of either bar is inside the other.
  expect_error(3, r, "of two of its 2 closed shells, which overlap", "", [](const TempCase& tc) {
    auto t = box({-0.3, -0.05, -0.05}, {0.3, 0.05, 0.05});
    const auto b = box({-0.05, -0.3, -0.04}, {0.05, 0.3, 0.04});
    t.insert(t.end(), b.begin(), b.end());
    write_stl(tc, t);
  });
}

// Shells that do not overlap stay valid: two apart, and a cube with a cavity (a smaller cube
// inside it, whose inside is outside the body by the parity rule).
TEST(ShapeErrors, StlOfSeparateOrNestedShellsChecksClean) {
  for (const auto& [lo, hi] : {std::pair{P3{0.3, 0.3, 0.3}, P3{0.5, 0.5, 0.5}},
                               std::pair{P3{0.05, 0.05, 0.05}, P3{0.15, 0.15, 0.15}}}) {
    TempCase tc("stl_shells");
    write_case(tc, 3, "region { type stl; file \"constant/triSurface/s.stl\"; }");
    auto t = box({0, 0, 0}, {0.2, 0.2, 0.2});
    const auto b = box(lo, hi);
    t.insert(t.end(), b.begin(), b.end());
    write_stl(tc, t);
    EXPECT_EQ(errors_of(tc), "") << lo[0];
  }
}

// Coordinates out of a double's reach: a cube scaled by 1e300 was
// reported as 12 zero-area triangles (its areas overflow); 1e400 is not a number at all.
TEST(ShapeErrors, StlCoordinatesTooLargeOrNotFinite) {
  const std::string r = "region { type stl; file \"constant/triSurface/s.stl\"; }";
  expect_error(3, r,
               "constant/bodies:4:24: file: constant/triSurface/s.stl has coordinates too large to compute with (the "
               "first: the facet at constant/triSurface/s.stl:2, a coordinate of magnitude 2e+299",
               "", [](const TempCase& tc) { write_stl(tc, box({-2e299, -2e299, -2e299}, {2e299, 2e299, 2e299})); });
  expect_error(3, r,
               "constant/triSurface/s.stl:5:1: ASCII STL: '1e400' is not a finite number; expected coordinates in "
               "metres",
               "", [](const TempCase& tc) {
                 write_file(tc, "constant/triSurface/s.stl",
                            "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1e400 0 0\nvertex 0 1 0\n"
                            "endloop\nendfacet\nendsolid s\n");
               });
  TempCase tc("stl_huge");
  write_case(tc, 3, r);
  write_stl(tc, box({-2e299, -2e299, -2e299}, {2e299, 2e299, 2e299}));
  const std::string e = errors_of(tc);
  EXPECT_EQ(e.find("zero-area"), std::string::npos) << e;
}

// ---- overlap and domain checks of 3D bodies -------------------------------------------

TEST(ShapeErrors, OverlappingSpheresAndASphereOutsideTheDomain) {
  expect_error(3, "region { type sphere; centre (0 0 0); radius 0.3; }",
               "region: body 'c' overlaps body 'b'", "}\nc\n{\n    material soil;\n    region { type sphere; centre (0.4 0 0); radius 0.2; }\n");
  expect_error(3, "region { type sphere; centre (0.9 0 0); radius 0.3; }",
               "constant/bodies:4:5: region: extends outside the domain of system/gridDict");
}

}  // namespace
}  // namespace scree::test
