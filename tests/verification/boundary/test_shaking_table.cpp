// A stiff elastic block resting on a shaking table (boundary/shakingTable, a node law that
// is the plugin's own kernel) follows the table.
//
// The table's velocity is V sin(w t) along x, V = w A, w = 2 pi f. The block's lowest
// natural frequency (a shear beam of height H fixed at its base: f_n = c_s / (4 H), with
// c_s = sqrt(G / rho)) is about 220 Hz here, 110 times the 2 Hz of the table: the block
// moves with the table as a rigid body, up to the ringing the start sets off. The table's
// acceleration jumps from 0 to w V at t = 0, which rings the first mode with a velocity of
// order V f / f_n (1% of V); the tolerance on the block's mean velocity is 5% of V (measured:
// 0.6%). Its mean displacement follows the table's, A (1 - cos w t), within 5% of its swing
// 2 A. Without the plugin's law the block would not move at all (checked too).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "scree_test.hpp"

namespace scree::test {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kA = 0.005, kF = 2.0;  // amplitude [m], frequency [Hz]

struct BlockMotion {
  double vx = 0, dx = 0;  // mass-weighted mean x-velocity [m/s] and x-displacement [m]
};

BlockMotion mean_motion(const Snapshot& s) {
  const BodySnapshot& b = s.bodies.at(0);
  const auto& v = b.find("velocity")->values;
  const auto& u = b.find("displacement")->values;
  const auto& m = b.find("mass")->values;
  BlockMotion r;
  double mass = 0;
  for (Index p = 0; p < b.n; ++p) {
    r.vx += m[p] * v[3 * p];
    r.dx += m[p] * u[3 * p];
    mass += m[p];
  }
  r.vx /= mass;
  r.dx /= mass;
  return r;
}

void write_case(const TempCase& tc, double end_time, const std::string& more_boundaries = "") {
  tc.write("system/controlDict",
           "endTime 1; deltaT 1e-4; adjustTimeStep yes; maxCo 0.5; writeInterval 1;");
  tc.write("system/gridDict", "dimension 2; lower (0 0); upper (0.4 0.2); cellSize 0.01;");
  tc.write("constant/g", "value (0 -9.81);");
  // E = 1e7 Pa, rho = 2000 kg/m^3: c_s = 44 m/s; H = 0.05 m: f_n = c_s / (4 H) = 220 Hz.
  tc.write("constant/materialProperties", "block { type linearElastic; E 1e7; nu 0.3; rho 2000; }");
  tc.write("constant/bodies", "b { material block; region { type rectangle; lower (0.1 0); upper (0.3 0.05); } "
                              "initialStress { type geostatic; K0 0.43; } }");
  tc.write("constant/boundaryConditions",
           "table { type shakingTable; face yMin; amplitude " + std::to_string(kA) + "; frequency " +
               std::to_string(kF) + "; direction (1 0); endTime " + std::to_string(end_time) + "; }" + more_boundaries);
}

TEST(ShakingTable, AStiffBlockMovesWithTheTable) {
  TempCase tc("shaking_table");
  write_case(tc, 1e300);
  Case c = Case::read(tc.dir(), runtime());
  Simulation sim(c, runtime(), options());
  const double w = 2 * kPi * kF, V = w * kA;
  for (double t : {0.0625, 0.125, 0.1875, 0.25, 0.3125, 0.375}) {
    sim.advance_to(t);
    const BlockMotion m = mean_motion(sim.snapshot());
    const double table_v = V * std::sin(w * sim.time());
    std::printf("t = %.4f s: block vx %.5f m/s, table %.5f m/s; block dx %.6f m, table %.6f m\n", sim.time(), m.vx,
                table_v, m.dx, kA * (1 - std::cos(w * sim.time())));
    EXPECT_NEAR(m.vx, table_v, 0.05 * V) << "at t = " << t;
    // The displacement, the integral of the velocity: 2 A at half a period.
    EXPECT_NEAR(m.dx, kA * (1 - std::cos(w * sim.time())), 0.05 * 2 * kA) << "at t = " << t;
  }
}

TEST(ShakingTable, OutsideItsWindowTheLawDoesNothing) {
  TempCase tc("shaking_table_off");
  write_case(tc, 0.0, " floor { type slip; face yMin; }");  // shaking ends before it starts
  Case c = Case::read(tc.dir(), runtime());
  Simulation sim(c, runtime(), options());
  sim.advance_to(0.125);
  EXPECT_LT(std::fabs(mean_motion(sim.snapshot()).vx), 1e-6);
}

}  // namespace
}  // namespace scree::test

SCREE_TEST_MAIN()
