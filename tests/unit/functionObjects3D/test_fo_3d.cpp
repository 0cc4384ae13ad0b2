// The function objects and the vtk writer on hand-made 3D particle sets whose answers
// follow from their geometry alone:
//   runOut along a diagonal of a rotated box = the box's support function;
//   runOut in radial mode on rings of points = the largest ring radius, equal fronts in
//   the x and z sectors of a symmetric deposit, the semi-axes of an elliptic one, and
//   the quantile of the ring radii;
//   surfaceProfile's height field of a stepped box = each step's top within half a
//   particle spacing (a particle centre lies half a spacing below the material's top);
//   particleProbes picks by 3D distance and writes the 6 tensor components;
//   the vtk writer's 3D arrays read back with VTK in ParaView's order;
//   and the user errors of the new keys (file:line, key, what was expected).
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataReader.h>

#include <cmath>

#include "test_util.hpp"

using namespace scree_test;
using scree::Snapshot;

namespace {

constexpr double kTol = 1e-11;
using P3 = std::array<double, 3>;

/// Particle centres filling the box [lo, hi] at spacing h (one particle per sub-cell of
/// side h, centres half a spacing inside the faces), as the solver seeds a `box` region.
std::vector<P3> lattice(P3 lo, P3 hi, double h) {
  std::vector<P3> out;
  const int n[3] = {static_cast<int>(std::lround((hi[0] - lo[0]) / h)), static_cast<int>(std::lround((hi[1] - lo[1]) / h)),
                    static_cast<int>(std::lround((hi[2] - lo[2]) / h))};
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i)
        out.push_back({lo[0] + (i + 0.5) * h, lo[1] + (j + 0.5) * h, lo[2] + (k + 0.5) * h});
  return out;
}

/// A snapshot of one body "left" at rest (velocity 0, mass 1 per particle) at `pos`.
Snapshot at_rest(const std::vector<P3>& pos, double time = 0, std::int64_t step = 0) {
  Snapshot s;
  s.dimension = 3;
  s.time = time;
  s.step = step;
  std::vector<std::int64_t> ids(pos.size());
  for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = static_cast<std::int64_t>(i);
  auto b = make_body("left", 0, pos, ids);
  add_field(b, "velocity", 3, std::vector<double>(3 * pos.size(), 0.0), "m/s");
  add_field(b, "mass", 1, std::vector<double>(pos.size(), 1.0), "kg");
  s.bodies = {b};
  return s;
}

/// The InputError's text for `text` as a function object's dictionary (no validation
/// against the spec: the plugin's own checks), or "" when none is thrown.
std::string input_error(const std::string& type, const std::string& text, const scree::SolverContext& ctx) {
  auto d = scree::Dictionary::parse("type " + type + "; " + text, "system/controlDict");
  try {
    runtime().registry().get(scree::PluginKind::functionObject, type, {}).function_object(d, ctx);
  } catch (const scree::InputError& e) {
    return e.what();
  }
  return "";
}

/// The validation errors of `text` against the function object's spec in `dimension`.
std::string validation_errors(const std::string& type, const std::string& text, int dimension) {
  auto d = scree::Dictionary::parse("type " + type + "; " + text, "system/controlDict");
  const auto& e = runtime().registry().get(scree::PluginKind::functionObject, type, {});
  std::vector<scree::InputError> errors;
  scree::validate(*e.spec, d, errors, dimension);
  std::string all;
  for (const auto& err : errors) all += std::string(err.what()) + "\n";
  return all;
}

}  // namespace

// ------------------------------------------------------------------ runOut

// A box of half-extents a x b (centres) rotated by phi about z, then shifted by t: its
// run-out along the unit direction u = (1 1 0)/sqrt2 from origin o is the support
// function of the rectangle, (t - o).u + a |u.e1| + b |u.e2| with e1 = (cos, sin),
// e2 = (-sin, cos). The height is its top centre (up = -g = +z).
TEST(RunOut3D, DiagonalRunOutOfARotatedBoxIsItsSupportFunction) {
  TempDir dir;
  const double h = 0.02, phi = 0.3, t[2] = {0.7, 0.4}, o[2] = {0.1, -0.2};
  auto box = lattice({-0.2, -0.1, 0.0}, {0.2, 0.1, 0.1}, h);  // centres span +-0.19, +-0.09, 0.01..0.09
  for (auto& p : box) {
    const double x = p[0], y = p[1];
    p[0] = t[0] + std::cos(phi) * x - std::sin(phi) * y;
    p[1] = t[1] + std::sin(phi) * x + std::cos(phi) * y;
  }
  const double a = 0.19, b = 0.09, s2 = std::sqrt(0.5);
  const double expected = ((t[0] - o[0]) + (t[1] - o[1])) * s2 + a * std::fabs(std::cos(phi) + std::sin(phi)) * s2 +
                          b * std::fabs(std::cos(phi) - std::sin(phi)) * s2;
  auto ctx = make_context(dir.path(), "diag", 3);
  make_function("runOut", "origin (0.1 -0.2 0); direction (3 3 0);", ctx)->execute(at_rest(box));
  const Csv c = read_csv(dir.path() / "postProcessing" / "diag" / "runOut.csv");
  EXPECT_NEAR(c.num(0, "runout [m]"), expected, kTol);
  EXPECT_NEAR(c.num(0, "height [m]"), 0.09, kTol);
  EXPECT_EQ(c.num(0, "particles [-]"), static_cast<double>(box.size()));
  EXPECT_EQ(c.header.at(3), "kinetic_energy [J]");
  EXPECT_EQ(c.header.at(8), "mass [kg]");

  // A space diagonal (1 1 1) of the unrotated box [0, 0.4] x [0, 0.2] x [0, 0.1]: the far
  // corner's centre (0.39 0.19 0.09) gives (0.39 + 0.19 + 0.09)/sqrt3 from the origin.
  make_function("runOut", "direction (1 1 1);", make_context(dir.path(), "space", 3))
      ->execute(at_rest(lattice({0, 0, 0}, {0.4, 0.2, 0.1}, h)));
  EXPECT_NEAR(read_csv(dir.path() / "postProcessing" / "space" / "runOut.csv").num(0, "runout [m]"),
              0.67 / std::sqrt(3.0), kTol);
}

namespace {

/// Rings of 36 points (every 10 degrees from +x) at radii 0.1, 0.2, ..., 1.0 around the
/// vertical axis (0 1 0) through (0.5 0 0.5), in `layers` layers y = 0, 0.05, ...;
/// x offsets scaled by sx (sx = 1: circles, a symmetric deposit).
std::vector<P3> rings(double sx = 1, int layers = 3) {
  std::vector<P3> out;
  for (int l = 0; l < layers; ++l)
    for (int k = 1; k <= 10; ++k)
      for (int a = 0; a < 36; ++a) {
        const double r = 0.1 * k, th = a * M_PI / 18;
        out.push_back({0.5 + sx * r * std::cos(th), 0.05 * l, 0.5 + r * std::sin(th)});
      }
  return out;
}

scree::SolverContext y_up_context(const fs::path& dir, const std::string& name) {
  auto ctx = make_context(dir, name, 3);
  ctx.gravity = {0, -9.81, 0};
  return ctx;
}

}  // namespace

TEST(RunOut3D, RadialModeGivesTheRadiusAndEqualSectorFrontsOfASymmetricDeposit) {
  TempDir dir;
  const fs::path pp = dir.path() / "postProcessing";
  make_function("runOut", "radial { centre (0.5 0 0.5); axis (0 1 0); directions ((1 0 0) (0 0 1) (-1 0 0)); }",
                y_up_context(dir.path(), "sym"))
      ->execute(at_rest(rings()));
  Csv c = read_csv(pp / "sym" / "runOut.csv");
  const std::vector<std::string> tail = {"particles [-]", "runout_+x [m]", "runout_+z [m]", "runout_-x [m]"};
  ASSERT_EQ(c.header.size(), 13u);
  EXPECT_EQ(std::vector<std::string>(c.header.end() - 4, c.header.end()), tail);
  EXPECT_NEAR(c.num(0, "runout [m]"), 1.0, kTol);   // the outer ring's radius
  EXPECT_NEAR(c.num(0, "height [m]"), 0.1, kTol);   // the top layer, along the axis from the centre
  EXPECT_NEAR(c.num(0, "runout_+x [m]"), 1.0, kTol);  // the outer ring's point at 0 degrees
  EXPECT_NEAR(c.num(0, "runout_+z [m]"), 1.0, kTol);
  EXPECT_NEAR(c.num(0, "runout_-x [m]"), 1.0, kTol);

  // The same deposit with the axis from gravity (default) and the 0.9 quantile: by the
  // symmetry of the rings the x and z sectors (points at -10, 0, 10 degrees) hold the
  // same distances, so the fronts are equal; the radius's 0.9 quantile is the 972nd of
  // 1080 radii (108 per ring): the 9th ring, 0.9 m.
  make_function("runOut",
                "frontQuantile 0.9; radial { centre (0.5 0 0.5); directions ((1 0 0) (0 0 1)); }",
                y_up_context(dir.path(), "q"))
      ->execute(at_rest(rings()));
  c = read_csv(pp / "q" / "runOut.csv");
  EXPECT_NEAR(c.num(0, "runout [m]"), 0.9, kTol);
  EXPECT_NEAR(c.num(0, "runout_+x [m]"), c.num(0, "runout_+z [m]"), kTol);
  EXPECT_LT(c.num(0, "runout_+x [m]"), 1.0);

  // An elliptic deposit, x stretched by 1.5: the fronts are the semi-axes, the radius the
  // larger one.
  make_function("runOut", "radial { centre (0.5 0 0.5); directions ((1 0 0) (0 0 1)); sectorHalfAngle 5; }",
                y_up_context(dir.path(), "ell"))
      ->execute(at_rest(rings(1.5)));
  c = read_csv(pp / "ell" / "runOut.csv");
  EXPECT_NEAR(c.num(0, "runout [m]"), 1.5, kTol);
  EXPECT_NEAR(c.num(0, "runout_+x [m]"), 1.5, kTol);
  EXPECT_NEAR(c.num(0, "runout_+z [m]"), 1.0, kTol);

  // A sector front is the offsets' component along its direction, not their length: a
  // point at 1 m and 10 degrees (inside the 15-degree sector) and one at 0.5 m and 0
  // degrees give cos(10 deg), where the largest distance from the axis is 1.
  const double th = 10 * M_PI / 180;
  make_function("runOut", "radial { centre (0.5 0 0.5); directions ((1 0 0)); }", y_up_context(dir.path(), "proj"))
      ->execute(at_rest({{0.5 + std::cos(th), 0, 0.5 + std::sin(th)}, {1.0, 0, 0.5}}));
  c = read_csv(pp / "proj" / "runOut.csv");
  EXPECT_NEAR(c.num(0, "runout_+x [m]"), std::cos(th), kTol);
  EXPECT_NEAR(c.num(0, "runout [m]"), 1.0, kTol);

  // A narrow sector (1 degree) around 5 degrees, between the rings' points (every 10
  // degrees): empty, nan; a direction off the axes is named by its index.
  make_function("runOut", "radial { centre (0.5 0 0.5); directions ((1 0 0.087488663525924)); sectorHalfAngle 1; }",
                y_up_context(dir.path(), "empty"))
      ->execute(at_rest(rings()));
  c = read_csv(pp / "empty" / "runOut.csv");
  EXPECT_EQ(c.header.back(), "runout_dir0 [m]");
  EXPECT_EQ(c.rows[0].back(), "nan");
}

// Radial mode in 2D: the axis is the vertical line through the centre; a deposit
// symmetric about it has equal fronts to the left and the right.
TEST(RunOut3D, RadialModeIn2D) {
  TempDir dir;
  Snapshot s;
  std::vector<P3> pos;
  for (double x : {-0.3, -0.1, 0.1, 0.3})
    for (double y : {0.05, 0.15}) pos.push_back({1 + x, y, 0});
  s = at_rest(pos);
  s.dimension = 2;
  make_function("runOut", "radial { centre (1 0); directions ((1 0) (-1 0)); }", make_context(dir.path(), "r2"))
      ->execute(s);
  const Csv c = read_csv(dir.path() / "postProcessing" / "r2" / "runOut.csv");
  EXPECT_EQ(c.header.at(3), "kinetic_energy [J/m]");
  EXPECT_NEAR(c.num(0, "runout [m]"), 0.3, kTol);
  EXPECT_NEAR(c.num(0, "runout_+x [m]"), 0.3, kTol);
  EXPECT_NEAR(c.num(0, "runout_-x [m]"), 0.3, kTol);
  EXPECT_NEAR(c.num(0, "height [m]"), 0.15, kTol);
}

TEST(RunOut3D, InputErrorsNameFileLineAndKey) {
  TempDir dir;
  auto ctx = make_context(dir.path(), "e", 3);
  std::string m = input_error("runOut", "direction (0 0 0);", ctx);
  EXPECT_NE(m.find("system/controlDict:1:"), std::string::npos) << m;
  EXPECT_NE(m.find("direction: expected a non-zero direction"), std::string::npos) << m;
  m = input_error("runOut", "radial { centre (0 0 0);\n directions ((1 0) (0 1 0)); }", ctx);
  EXPECT_NE(m.find("system/controlDict:2:"), std::string::npos) << m;
  EXPECT_NE(m.find("radial.directions: element 1 must be a direction of 3 numbers"), std::string::npos) << m;
  m = input_error("runOut", "radial { centre (0 0 0); directions ((0 0 2)); }", ctx);  // along the axis (+z)
  EXPECT_NE(m.find("parallel to the axis"), std::string::npos) << m;
  m = input_error("runOut", "radial { centre (0 0 0); directions ((1 0 0) (2 0 0)); }", ctx);
  EXPECT_NE(m.find("repeats an earlier direction"), std::string::npos) << m;
  m = input_error("runOut", "direction (1 0 0); radial { centre (0 0 0); }", ctx);
  EXPECT_NE(m.find("direction: not with radial"), std::string::npos) << m;
  m = input_error("runOut", "radial { centre (0 0 0); axis (0 0 0); }", ctx);
  EXPECT_NE(m.find("axis: expected a non-zero direction"), std::string::npos) << m;
  // Vectors of the wrong length are caught by the spec's validation, before any plugin
  // exists, located, naming the key.
  m = validation_errors("runOut", "origin (0 0); radial { centre (1 2); sectorHalfAngle 0; }", 3);
  EXPECT_NE(m.find("system/controlDict:1:"), std::string::npos) << m;
  EXPECT_NE(m.find("origin"), std::string::npos) << m;
  EXPECT_NE(m.find("centre"), std::string::npos) << m;
  EXPECT_NE(m.find("sectorHalfAngle"), std::string::npos) << m;
  EXPECT_EQ(validation_errors("runOut", "radial { centre (1 2 3); directions ((1 0 0)); }", 3), "");
  // The rules that need no case are also the spec's (scree --check reports them before
  // any plugin is built), with the constructor's messages.
  m = validation_errors("runOut", "radial { centre (0 0 0);\n directions ((1 0) (0 1 0)); }", 3);
  EXPECT_NE(m.find("system/controlDict:2:"), std::string::npos) << m;
  EXPECT_NE(m.find("radial.directions: element 1 must be a direction of 3 numbers"), std::string::npos) << m;
  m = validation_errors("runOut", "direction (0 0 0);", 3);
  EXPECT_NE(m.find("direction: expected a non-zero direction"), std::string::npos) << m;
  m = validation_errors("runOut", "radial { centre (0 0 0); axis (0 0 1); directions ((0 0 2)); }", 3);
  EXPECT_NE(m.find("parallel to the axis"), std::string::npos) << m;
  m = validation_errors("runOut", "up (0 0 1); radial { centre (0 0 0); }", 3);
  EXPECT_NE(m.find("up: not with radial"), std::string::npos) << m;
}

// ------------------------------------------------------------------ surfaceProfile

// A stepped box: x in [0, 0.2] has its top at z = 0.3, x in [0.2, 0.4] at z = 0.2, over
// y in [0, 0.1], particles at spacing h = 0.025 (2 per 0.05 cell): the height of every
// 0.05 bin is its step's top within h/2 (the top particles' centres, h/2 below), and it
// holds 2 x 2 x (top / h) particles. A hole (no particles over x in [0.1, 0.15], y in
// [0.05, 0.1]) gives nan and 0.
TEST(SurfaceProfile3D, HeightFieldOfAStepppedBoxIsItsTop) {
  TempDir dir;
  const double h = 0.025;
  auto pos = lattice({0, 0, 0}, {0.2, 0.1, 0.3}, h);
  for (const auto& p : lattice({0.2, 0, 0}, {0.4, 0.1, 0.2}, h)) pos.push_back(p);
  std::vector<P3> holed;
  for (const auto& p : pos)
    if (!(p[0] > 0.1 && p[0] < 0.15 && p[1] > 0.05)) holed.push_back(p);
  auto s = at_rest(holed, 0.5, 3);
  make_function("surfaceProfile", "binWidth 0.05;", make_context(dir.path(), "hf", 3))->execute(s);
  const Csv c = read_csv(dir.path() / "postProcessing" / "hf" / "0.5.csv");
  const std::vector<std::string> header = {"x [m]", "y [m]", "height [m]", "particles [-]"};
  EXPECT_EQ(c.header, header);
  ASSERT_EQ(c.rows.size(), 16u);  // 8 x 2 bins, x fastest
  for (std::size_t r = 0; r < c.rows.size(); ++r) {
    const double x = 0.025 + 0.05 * static_cast<double>(r % 8), y = 0.025 + 0.05 * static_cast<double>(r / 8);
    EXPECT_NEAR(c.num(r, "x [m]"), x, kTol) << r;
    EXPECT_NEAR(c.num(r, "y [m]"), y, kTol) << r;
    if (r == 10) {  // x = 0.125, y = 0.075: the hole
      EXPECT_EQ(c.rows[r][2], "nan");
      EXPECT_EQ(c.num(r, "particles [-]"), 0);
      continue;
    }
    const double top = x < 0.2 ? 0.3 : 0.2;
    EXPECT_LE(std::fabs(c.num(r, "height [m]") - top), 0.5 * h + kTol) << r;
    EXPECT_EQ(c.num(r, "particles [-]"), 4 * std::lround(top / h)) << r;
  }

  // Up = +y (gravity along -y): the horizontal axes are x and z.
  make_function("surfaceProfile", "binWidth 0.1; origin (0 0 0);", y_up_context(dir.path(), "yup"))->execute(s);
  const Csv cy = read_csv(dir.path() / "postProcessing" / "yup" / "0.5.csv");
  EXPECT_EQ(cy.header.at(0), "x [m]");
  EXPECT_EQ(cy.header.at(1), "z [m]");
  EXPECT_NEAR(cy.num(0, "height [m]"), 0.0875, kTol);  // the highest y centre, 0.1 - h/2

  // A section along x through y = 0.025 (width 0.05: the first row of bins), with a fixed
  // range: the 2D profile's columns; the hole is outside it.
  make_function("surfaceProfile", "binWidth 0.05; direction (1 0 0); origin (0 0.025 0); width 0.05; range (0 0.4);",
                make_context(dir.path(), "sec", 3))
      ->execute(s);
  const Csv cs = read_csv(dir.path() / "postProcessing" / "sec" / "0.5.csv");
  const std::vector<std::string> sh = {"distance [m]", "height [m]", "particles [-]"};
  EXPECT_EQ(cs.header, sh);
  ASSERT_EQ(cs.rows.size(), 8u);
  for (std::size_t r = 0; r < 8; ++r) {
    const double top = r < 4 ? 0.3 : 0.2;
    EXPECT_LE(std::fabs(cs.num(r, "height [m]") - top), 0.5 * h + kTol) << r;
    EXPECT_EQ(cs.num(r, "particles [-]"), 4 * std::lround(top / h)) << r;  // 2 x-columns x 2 y-rows
  }
}

TEST(SurfaceProfile3D, InputErrors) {
  TempDir dir;
  EXPECT_NE(input_error("surfaceProfile", "width 0.1;", make_context(dir.path(), "w", 3)).find("width: only for a 3D section"),
            std::string::npos);
  EXPECT_NE(input_error("surfaceProfile", "direction (1 0); width 0.1;", make_context(dir.path(), "w2")).find("system/controlDict:1:"),
            std::string::npos);
  std::string m = input_error("surfaceProfile", "range (0 1);", make_context(dir.path(), "r", 3));
  EXPECT_NE(m.find("range: expected (a1 b1 a2 b2)"), std::string::npos) << m;
  m = input_error("surfaceProfile", "direction (0 0 1); width 0.1;", make_context(dir.path(), "v", 3));
  EXPECT_NE(m.find("direction: parallel to up"), std::string::npos) << m;
  // The same rules in the spec's check (scree --check), where a vector given tells the
  // dimension.
  EXPECT_NE(validation_errors("surfaceProfile", "width 0.1;", 3).find("width: only for a 3D section"),
            std::string::npos);
  EXPECT_NE(validation_errors("surfaceProfile", "direction (1 0);\nwidth 0.1;", 2).find("system/controlDict:2:"),
            std::string::npos);
  m = validation_errors("surfaceProfile", "origin (0 0 0); range (0 1);", 3);
  EXPECT_NE(m.find("range: expected (a1 b1 a2 b2)"), std::string::npos) << m;
  EXPECT_EQ(validation_errors("surfaceProfile", "origin (0 0 0); range (0 1 0 1);", 3), "");
  EXPECT_EQ(validation_errors("surfaceProfile", "direction (1 0 0); width 0.1; range (0 1);", 3), "");
}

// ------------------------------------------------------------------ particleProbes

// Two particles that differ only in z: the probe at z = 0.9 must pick the upper one (a
// 2D distance could not tell them apart), and a 3D probe writes x y z and the 6 stress
// components.
TEST(ParticleProbes3D, PicksBy3DDistanceAndWritesSixTensorComponents) {
  TempDir dir;
  auto s = at_rest({{0.5, 0.5, 0.1}, {0.5, 0.5, 0.9}});
  add_field(s.bodies[0], "stress", 6, {1, 2, 3, 4, 5, 6, 11, 12, 13, 14, 15, 16}, "Pa");
  make_function("particleProbes", "points ((0.5 0.5 0.8)); names (top); fields (stress);",
                make_context(dir.path(), "pr", 3))
      ->execute(s);
  const Csv c = read_csv(dir.path() / "postProcessing" / "pr" / "top.csv");
  const std::vector<std::string> header = {"time [s]", "x [m]", "y [m]", "z [m]", "stress_xx [Pa]", "stress_yy [Pa]",
                                           "stress_zz [Pa]", "stress_xy [Pa]", "stress_yz [Pa]", "stress_zx [Pa]"};
  EXPECT_EQ(c.header, header);
  EXPECT_NEAR(c.num(0, "z [m]"), 0.9, kTol);
  EXPECT_EQ(c.num(0, "stress_yz [Pa]"), 15);
  EXPECT_EQ(c.num(0, "stress_zx [Pa]"), 16);
  const std::string m = input_error("particleProbes", "points ((0.5 0.5 0.8)\n (0.5 0.5));", make_context(dir.path(), "bad", 3));
  EXPECT_NE(m.find("system/controlDict:2:"), std::string::npos) << m;
  EXPECT_NE(m.find("points: element 2 must be a point of 3 numbers"), std::string::npos) << m;
}

// lineProfile's ends and energies' origin are vectors of one component per dimension:
// a 2-component end in 3D is a located validation error naming the key.
TEST(LineProfile3D, TwoComponentEndIsALocatedError) {
  const std::string m = validation_errors("lineProfile", "start (0 0 0);\nend (1 1);", 3);
  EXPECT_NE(m.find("system/controlDict:2:"), std::string::npos) << m;
  EXPECT_NE(m.find("end"), std::string::npos) << m;
  EXPECT_EQ(validation_errors("lineProfile", "start (0 0 0); end (1 1 1);", 3), "");
  EXPECT_NE(validation_errors("energies", "origin (0 0);", 3).find("origin"), std::string::npos);
}

// ------------------------------------------------------------------ vtk writer

// A 3D snapshot written by the vtk writer and read back with VTK's XML reader (the reader
// ParaView uses): positions with their z, velocity as 3 components X Y Z, stress as 6
// components XX YY ZZ XY YZ XZ (ParaView's symmetric-tensor order), the snapshot's Voigt
// xx yy zz xy yz zx landing on them one to one (zx = xz).
TEST(VtkWriter3D, ParticlesCarry3DVectorsAndSymmetricTensorsInParaViewOrder) {
  TempDir dir;
  auto ctx = make_context(dir.path(), "particles", 3);
  auto w = make_writer("type vtk;", ctx);
  auto s = at_rest({{0.1, 0.2, 0.3}, {0.4, 0.5, 0.6}}, 0.0, 0);
  s.bodies[0].fields.clear();
  add_field(s.bodies[0], "velocity", 3, {1, 2, 3, 4, 5, 6}, "m/s");
  add_field(s.bodies[0], "stress", 6, {-1, -2, -3, 0.4, 0.5, 0.6, -11, -12, -13, 1.4, 1.5, 1.6}, "Pa");
  add_field(s.bodies[0], "bodyId", 1, {0, 0});
  w->write(s);
  w->finish();
  vtkNew<vtkXMLPolyDataReader> r;
  r->SetFileName((dir.path() / "VTK" / "particles_0.vtp").c_str());
  r->Update();
  ASSERT_EQ(r->GetErrorCode(), 0u);
  vtkPolyData* pd = r->GetOutput();
  ASSERT_EQ(pd->GetNumberOfPoints(), 2);
  double x[3];
  pd->GetPoint(1, x);
  EXPECT_DOUBLE_EQ(x[2], 0.6);
  vtkDataArray* v = pd->GetPointData()->GetArray("velocity");
  ASSERT_NE(v, nullptr);
  ASSERT_EQ(v->GetNumberOfComponents(), 3);
  EXPECT_STREQ(v->GetComponentName(2), "Z");
  EXPECT_DOUBLE_EQ(v->GetComponent(1, 2), 6);
  vtkDataArray* st = pd->GetPointData()->GetArray("stress");
  ASSERT_NE(st, nullptr);
  ASSERT_EQ(st->GetNumberOfComponents(), 6);
  const char* names[] = {"XX", "YY", "ZZ", "XY", "YZ", "XZ"};
  const double want[] = {-11, -12, -13, 1.4, 1.5, 1.6};
  for (int c = 0; c < 6; ++c) {
    EXPECT_STREQ(st->GetComponentName(c), names[c]) << c;
    EXPECT_DOUBLE_EQ(st->GetComponent(1, c), want[c]) << names[c];
  }
  EXPECT_EQ(pd->GetPointData()->GetTensors(), st);  // ParaView shows it as a tensor
}
