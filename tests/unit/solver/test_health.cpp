// The health checks (time/step_control.hpp): a non-finite value, found by the grid update
// in the nodal velocities and forces it reaches, stops the run in the step it appeared, and
// the diagnosis names the particle (found in the frozen state), its body and material, the
// field, the value and the step. (The scree-level cases, a huge E,
// a huge g and a fixed step far above the stable one, are tests/broken/variants/health_*.)
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <regex>
#include <string>

#include "scree_test.hpp"

namespace scree::test {
namespace {

TEST(Health, ANonFiniteVelocityStopsTheRunInItsStepWithTheParticleNamed) {
  TempCase tc("health");
  tc.write("system/controlDict", "endTime 0.1; deltaT 1e-4; writeInterval 0.1;");
  tc.write("system/gridDict", "dimension 2; lower (0 0); upper (0.4 0.4); cellSize 0.02;");
  tc.write("constant/g", "value (0 -9.81);");
  tc.write("constant/materialProperties", "sand { type linearElastic; E 1e6; nu 0.3; rho 1000; }");
  tc.write("constant/bodies", "block { material sand; region { type rectangle; lower (0.1 0.1); upper (0.3 0.2); } }");
  tc.write("constant/boundaryConditions", "floor { type fixed; face yMin; }");
  Case c = Case::read(tc.dir(), runtime());
  Simulation sim(c, runtime(), options(1));
  const Snapshot s0 = sim.snapshot();
  const std::size_t n = static_cast<std::size_t>(s0.bodies.at(0).n);
  std::vector<double> v(2 * n, 0.0);
  const std::size_t bad = n / 2;  // one point's velocity, as a blown-up update would leave it
  v[2 * bad + 1] = std::numeric_limits<double>::quiet_NaN();
  sim.set_velocities(0, v);
  std::string what;
  try {
    sim.advance_to(0.1);
  } catch (const RunFailure& e) {
    what = e.what();
  }
  ASSERT_FALSE(what.empty()) << "a NaN velocity ran to the end without a word";
  // The step that met the NaN: its scatter spreads it to the nodes, the stress update of
  // the points around reads it back, and the clock stops after that step.
  EXPECT_NE(what.find("stopped in step 0 "), std::string::npos) << what;
  const std::regex line("(position|velocity|stress) (x|y|xx|yy|zz|xy) = -?nan \\(not finite\\) of particle (\\d+) of "
                        "body 'block' \\(material 'sand', linearElastic, constant/materialProperties:1:1\\), found in "
                        "step 0; (\\d+) non-finite value\\(s\\)");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(what, m, line)) << what;
  // The points whose stencils share a node with the NaN point: its own cell's neighbours.
  const Snapshot s = sim.snapshot();
  const BodySnapshot& b = s.bodies[0];
  const std::int64_t id = std::stoll(m[3].str());
  Index at = -1;
  for (Index i = 0; i < b.n; ++i)
    if (b.id[i] == id) at = i;
  ASSERT_GE(at, 0);
  const double h = 0.02;
  for (int d = 0; d < 2; ++d)
    EXPECT_LE(std::fabs(b.position[3 * at + d] - s0.bodies[0].position[3 * bad + d]), 2 * h)
        << "the particle named is next to the one made NaN";
  EXPECT_EQ(sim.stats().steps >= 1, true);
  EXPECT_EQ(s.step, 1) << "one step advanced the clock; those after the failure did not";
}


// An elastic block falling freely, USL with linear shape functions, at a fixed step of
// Courant number 0.32 (P-wave speed 64 m/s, dt 1e-4 s, h 0.02 m): where its points linger
// just past a cell face the nodes of the new cell carry a sliver of their mass and a whole
// share of their stress's force, and USL takes the strain rate from those nodes' updated
// velocities. The run stops, and its diagnosis names the cause and the settings that keep it
// stable; with massTolerance 0.1 the same block falls for 0.1 s, every point within 2% of
// the fall and of the velocity of free fall: a point loses the weight it shares with the
// nodes left unaccelerated while it crosses a face, a small share of a point's weight for a
// few steps of each crossing (GIMP, whose domains leave no such nodes, falls exactly: the
// two-phase block in tests/verification/twophase).
void write_falling_elastic_block(const TempCase& tc, const std::string& schemes) {
  tc.write("system/controlDict", "endTime 0.1; deltaT 1e-4; writeInterval 0.1;");
  tc.write("system/gridDict", "dimension 2; lower (0 0); upper (1.2 0.3); cellSize 0.02;");
  tc.write("system/mpmSchemes", "updateScheme USL; shapeFunction linear; " + schemes);
  tc.write("constant/g", "value (0 -9.81);");
  tc.write("constant/materialProperties", "m { type linearElastic; E 6e6; nu 0.3; rho 2000; }");
  tc.write("constant/bodies", "block { material m; region { type rectangle; lower (0.1 0.1); upper (0.4 0.16); } }");
  tc.write("constant/boundaryConditions", "");
}

TEST(Health, AFallingBlockUnstableUnderUSLWithLinearShapesIsDiagnosed) {
  TempCase tc("usl_linear");
  write_falling_elastic_block(tc, "");
  Case c = Case::read(tc.dir(), runtime());
  Simulation sim(c, runtime(), options(1));
  std::string what;
  try {
    sim.advance_to(0.1);
  } catch (const RunFailure& e) {
    what = e.what();
  }
  ASSERT_FALSE(what.empty()) << "the block ran to the end: the test no longer shows the instability it documents";
  EXPECT_NE(what.find("runs USL with linear shape functions"), std::string::npos) << what;
  EXPECT_NE(what.find("massTolerance 0.1 (system/mpmSchemes"), std::string::npos) << what;
  EXPECT_NE(what.find("shapeFunction gimp"), std::string::npos) << what;
  EXPECT_NE(what.find("updateScheme USF or MUSL"), std::string::npos) << what;

  TempCase ok("usl_linear_mass_tolerance");
  write_falling_elastic_block(ok, "massTolerance 0.1;");
  Case c2 = Case::read(ok.dir(), runtime());
  Simulation sim2(c2, runtime(), options(1));
  const BodySnapshot b0 = sim2.snapshot().bodies.at(0);
  const double t = 0.1, g = 9.81, dt = 1e-4, fall = 0.5 * g * t * (t + dt);  // x0 - g t (t + dt) / 2
  sim2.advance_to(t);
  const BodySnapshot b = sim2.snapshot().bodies.at(0);
  std::map<std::int64_t, std::size_t> start;
  for (Index i = 0; i < b0.n; ++i) start[b0.id[static_cast<std::size_t>(i)]] = static_cast<std::size_t>(i);
  double dy = 0, dv = 0;
  for (Index i = 0; i < b.n; ++i) {
    const std::size_t k = static_cast<std::size_t>(i), k0 = start.at(b.id[k]);
    dy = std::max(dy, std::fabs(b.position[3 * k + 1] - (b0.position[3 * k0 + 1] - fall)));
    dv = std::max(dv, std::fabs(field(b, "velocity").values[3 * k + 1] + g * t));
  }
  std::printf("massTolerance 0.1: largest departure from free fall %.3g m of %.3g, %.3g m/s of %.3g\n", dy, fall, dv,
              g * t);
  EXPECT_LT(dy, 0.02 * fall);
  EXPECT_LT(dv, 0.02 * g * t);
}

}  // namespace
}  // namespace scree::test
