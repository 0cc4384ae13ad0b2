// A stiff elastic block resting on a shaking table (boundary/shakingTable, a node law that
// is the plugin's own kernel) follows the table: a sine, an acceleration record, and a
// `fixed` base whose velocity is a function of time.
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

void write_case(const TempCase& tc, double end_time, const std::string& more_boundaries = "",
                const std::string& motion = "") {
  tc.write("system/controlDict",
           "endTime 1; deltaT 1e-4; adjustTimeStep yes; maxCo 0.5; writeInterval 1;");
  tc.write("system/gridDict", "dimension 2; lower (0 0); upper (0.4 0.2); cellSize 0.01;");
  tc.write("constant/g", "value (0 -9.81);");
  // E = 1e7 Pa, rho = 2000 kg/m^3: c_s = 44 m/s; H = 0.05 m: f_n = c_s / (4 H) = 220 Hz.
  tc.write("constant/materialProperties", "block { type linearElastic; E 1e7; nu 0.3; rho 2000; }");
  tc.write("constant/bodies", "b { material block; region { type rectangle; lower (0.1 0); upper (0.3 0.05); } "
                              "initialStress { type geostatic; K0 0.43; } }");
  tc.write("constant/boundaryConditions",
           "table { type shakingTable; face yMin; " +
               (motion.empty() ? "amplitude " + std::to_string(kA) + "; frequency " + std::to_string(kF) + ";" : motion) +
               " direction (1 0); endTime " + std::to_string(end_time) + "; }" + more_boundaries);
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

// The same table driven by its acceleration record, a(t) = w V cos(w t), sampled every
// millisecond in a CSV file in units of g: the table's velocity is the record's integral,
// exact for the piecewise-linear record, which differs from V sin(w t) by at most
// dt_r^2 w^2 V / 8 (the trapezoid rule's error over a quarter period, 2e-5 V here). So the
// block follows the sine within the tolerances above, and the two tables' blocks agree
// with each other within 1e-3 V (the ringing, set off the same way, cancels).
TEST(ShakingTable, AnAccelerationRecordDrivesTheTableAsItsIntegral) {
  const double w = 2 * kPi * kF, V = w * kA, g = 9.80665, dt_r = 1e-3;
  std::string csv = "time, acceleration\n";
  char row[64];
  for (int i = 0; i * dt_r <= 0.5 + 1e-12; ++i) {
    std::snprintf(row, sizeof row, "%.6f, %.17g\n", i * dt_r, w * V * std::cos(w * i * dt_r) / g);
    csv += row;
  }
  TempCase rec("shaking_table_record"), sine("shaking_table_sine");
  rec.write("constant/record.csv", csv);
  write_case(rec, 1e300, "",
             "acceleration { type csvFile; file \"constant/record.csv\"; columns (time acceleration); unit g; }");
  write_case(sine, 1e300);
  Case cr = Case::read(rec.dir(), runtime()), cs = Case::read(sine.dir(), runtime());
  Simulation a(cr, runtime(), options()), b(cs, runtime(), options());
  for (double t : {0.0625, 0.125, 0.25, 0.375}) {
    a.advance_to(t);
    b.advance_to(t);
    const BlockMotion ma = mean_motion(a.snapshot()), mb = mean_motion(b.snapshot());
    std::printf("t = %.4f s: block vx %.6f m/s on the record's table, %.6f on the sine's (V sin w t = %.6f)\n",
                a.time(), ma.vx, mb.vx, V * std::sin(w * a.time()));
    EXPECT_NEAR(ma.vx, V * std::sin(w * a.time()), 0.05 * V) << "at t = " << t;
    EXPECT_NEAR(ma.vx, mb.vx, 1e-3 * V) << "at t = " << t;
    EXPECT_NEAR(ma.dx, mb.dx, 1e-3 * 2 * kA) << "at t = " << t;
  }
}

TEST(ShakingTable, ARecordAndASineAreNotBothGiven) {
  TempCase tc("shaking_table_both");
  write_case(tc, 1e300, "", "amplitude 0.01; frequency 2; acceleration table ((0 0) (1 1));");
  try {
    Case c = Case::read(tc.dir(), runtime());
    Simulation sim(c, runtime(), options());
    FAIL() << "a table with both a record and a sine was accepted";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("not both"), std::string::npos) << e.what();
  }
}

// A `fixed` base whose value varies in time (a velocity table: a ramp of a = 0.1 m/s^2
// along x) carries the block as the table does: its mean velocity a t and displacement
// a t^2 / 2. The ramp starts with an acceleration jump of 0.1 m/s^2, which rings the first
// mode with a velocity of order a / (2 pi f_n) = 7e-5 m/s, 0.3% of a t at 0.25 s; the
// tolerance is 2% of each. With the value held constant at zero the block stays put
// (the wall is still a no-slip wall).
TEST(ShakingTable, AFixedWallWhoseValueVariesInTimeCarriesTheBlock) {
  const double a = 0.1;
  TempCase tc("fixed_ramp");
  write_case(tc, 1e300);
  tc.write("constant/boundaryConditions", "base { type fixed; face yMin; value table ((0 (0 0)) (1 (0.1 0))); }");
  Case c = Case::read(tc.dir(), runtime());
  Simulation sim(c, runtime(), options());
  for (double t : {0.25, 0.5}) {
    sim.advance_to(t);
    const BlockMotion m = mean_motion(sim.snapshot());
    std::printf("t = %.4f s: block vx %.6f m/s (a t = %.6f), dx %.7f m (a t^2/2 = %.7f)\n", sim.time(), m.vx,
                a * sim.time(), m.dx, 0.5 * a * sim.time() * sim.time());
    EXPECT_NEAR(m.vx, a * sim.time(), 0.02 * a * sim.time()) << "at t = " << t;
    EXPECT_NEAR(m.dx, 0.5 * a * sim.time() * sim.time(), 0.02 * 0.5 * a * sim.time() * sim.time()) << "at t = " << t;
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
