// A run reproduces itself bit for bit on one CPU thread, however its steps are cut into
// chunks. The host cuts the loop into chunks of steps (at outputs, progress reports and
// particle sorts); where a chunk ends depends on the wall time in a real run. Steps that
// idle on a target time (dt = 0) are no-ops, but their number depends on where the chunk
// ended, so a particle sort scheduled by the step index fell at different points of the
// flow from run to run (a sort changes the order of the additions into the nodes, and so
// the last bits). Sorts now follow the steps that advanced the clock.
#include <gtest/gtest.h>

#include <cstring>

#include "scree_test.hpp"

namespace scree::test {
namespace {

/// A block sliding to rest on a rough floor: its speed, and with it the adaptive step,
/// changes through the run, so the chunks' estimates of the steps to a target overshoot.
Snapshot slide(int progress_interval) {
  TempCase tc("reproducible");
  tc.write("system/controlDict", "endTime 1; deltaT 1e-3; adjustTimeStep yes; maxCo 0.4; writeInterval 1; "
                                 "progressInterval " + std::to_string(progress_interval) + ";");
  tc.write("system/mpmSchemes", "sortInterval 7;");
  tc.write("system/gridDict", "dimension 2; lower (0 0); upper (1.2 0.3); cellSize 0.02;");
  tc.write("constant/g", "value (0 -9.81);");
  tc.write("constant/materialProperties", "m { type linearElastic; E 2e5; nu 0.3; rho 1000; }");
  tc.write("constant/bodies", "b { material m; velocity (3 0); region { type rectangle; lower (0.1 0); "
                              "upper (0.3 0.06); } }");
  tc.write("constant/boundaryConditions", "floor { type friction; face yMin; coefficient 0.5; }");
  Case c = Case::read(tc.dir(), runtime());
  Simulation sim(c, runtime(), options(1));
  for (int k = 1; k <= 40; ++k) sim.advance_to(0.0073 * k);  // 40 targets, each a chunk boundary
  return sim.snapshot();
}

TEST(Reproducible, ChunkingDoesNotChangeABit) {
  const Snapshot a = slide(3), b = slide(17);
  ASSERT_EQ(a.bodies.size(), 1u);
  const BodySnapshot &A = a.bodies[0], &B = b.bodies[0];
  ASSERT_EQ(A.n, B.n);
  for (const FieldData& fa : A.fields) {
    const FieldData* fb = B.find(fa.name.c_str());
    ASSERT_NE(fb, nullptr);
    ASSERT_EQ(fa.values.size(), fb->values.size());
    EXPECT_EQ(std::memcmp(fa.values.data(), fb->values.data(), fa.values.size() * sizeof(Real)), 0)
        << "field " << fa.name << " differs between two chunkings of the same run";
  }
  EXPECT_EQ(std::memcmp(A.id.data(), B.id.data(), A.id.size() * sizeof(A.id[0])), 0) << "particle order";
  EXPECT_EQ(a.step, b.step) << "the step written with the output counts the steps that advanced the clock";
  EXPECT_EQ(a.time, b.time);
}

}  // namespace
}  // namespace scree::test
