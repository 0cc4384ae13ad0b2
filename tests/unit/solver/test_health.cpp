// The health checks (time/step_control.hpp): a non-finite value, found by the grid update
// in the nodal velocities and forces it reaches, stops the run in the step it appeared, and
// the diagnosis names the particle (found in the frozen state), its body and material, the
// field, the value and the step. (The scree-level cases, a huge E,
// a huge g and a fixed step far above the stable one, are tests/broken/variants/health_*.)
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
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

}  // namespace
}  // namespace scree::test
