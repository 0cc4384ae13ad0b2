// Tests of the function objects (plugins/functionObjects) on hand-made snapshots with
// analytic answers: runOut (front, quantile front, height window, kinetic energy, mean
// velocity, 3D), energies, particleProbes (nearest particle, tracking by id through a
// reordering, missing particles, field expansion), surfaceProfile, and the CSV rules
// (header with units, one flushed row per execution, the final state not repeated,
// restart keeps earlier rows, fresh run replaces the file) and input errors.
#include <cmath>

#include "test_util.hpp"

using namespace scree_test;
using scree::Snapshot;

namespace {

/// Body "left": 4 particles with masses 1..4 and known velocities; body "right": one
/// particle far away at x = 5.
Snapshot layout(double time, std::int64_t step) {
  Snapshot s;
  s.time = time;
  s.step = step;
  auto a = make_body("left", 0, {{0.1, 0.0, 0}, {0.5, 0.3, 0}, {0.9, 0.1, 0}, {2.0, 0.05, 0}}, {0, 1, 2, 3});
  add_field(a, "velocity", 3, {1, 0, 0, 0, 2, 0, 1, 1, 0, 3, 4, 0}, "m/s");
  add_field(a, "mass", 1, {1, 2, 3, 4}, "kg");
  auto b = make_body("right", 1, {{5.0, 0.2, 0}}, {4});
  add_field(b, "velocity", 3, {0, 0, 0}, "m/s");
  add_field(b, "mass", 1, {10}, "kg");
  s.bodies = {a, b};
  return s;
}

constexpr double kTol = 1e-11;

}  // namespace

TEST(RunOut, FrontHeightEnergyAndVelocities) {
  TempDir dir;
  auto ctx = make_context(dir.path(), "front");
  auto f = make_function("runOut", "bodies (left); origin (0.1 0);", ctx);
  f->execute(layout(0.0, 0));
  f->execute(layout(0.5, 7));
  f->execute(layout(0.5, 7));  // the final state handed over twice: one row
  const Csv c = read_csv(dir.path() / "postProcessing" / "front" / "runOut.csv");
  const std::vector<std::string> header = {"time [s]",
                                           "runout [m]",
                                           "height [m]",
                                           "kinetic_energy [J/m]",
                                           "max_speed [m/s]",
                                           "mean_velocity_x [m/s]",
                                           "mean_velocity_y [m/s]",
                                           "mass [kg/m]",
                                           "particles [-]"};
  EXPECT_EQ(c.header, header);
  ASSERT_EQ(c.rows.size(), 2u);
  EXPECT_EQ(c.num(1, "time [s]"), 0.5);
  EXPECT_NEAR(c.num(1, "runout [m]"), 1.9, kTol);  // furthest particle at x = 2, origin 0.1
  EXPECT_NEAR(c.num(1, "height [m]"), 0.3, kTol);  // up = -g = +y
  // 1/2 (1*1 + 2*4 + 3*2 + 4*25)
  EXPECT_NEAR(c.num(1, "kinetic_energy [J/m]"), 57.5, kTol);
  EXPECT_NEAR(c.num(1, "max_speed [m/s]"), 5.0, kTol);
  EXPECT_NEAR(c.num(1, "mean_velocity_x [m/s]"), 1.6, kTol);  // momentum (16, 23) / mass 10
  EXPECT_NEAR(c.num(1, "mean_velocity_y [m/s]"), 2.3, kTol);
  EXPECT_EQ(c.num(1, "mass [kg/m]"), 10);
  EXPECT_EQ(c.num(1, "particles [-]"), 4);
}

TEST(RunOut, AllBodiesQuantileWindowAndDirection) {
  TempDir dir;
  auto ctx = make_context(dir.path(), "all");
  make_function("runOut", "", ctx)->execute(layout(0, 0));
  Csv c = read_csv(dir.path() / "postProcessing" / "all" / "runOut.csv");
  EXPECT_NEAR(c.num(0, "runout [m]"), 5.0, kTol);  // body "right" included
  EXPECT_NEAR(c.num(0, "kinetic_energy [J/m]"), 57.5, kTol);

  // Distances 0, 0.4, 0.8, 1.9: the 0.75 quantile is the 3rd smallest. The window
  // [0.5, 1] holds only the particle at 0.8 (height 0.1).
  make_function("runOut", "bodies (left); origin (0.1 0); frontQuantile 0.75; heightWindow (0.5 1);",
                make_context(dir.path(), "q"))
      ->execute(layout(0, 0));
  c = read_csv(dir.path() / "postProcessing" / "q" / "runOut.csv");
  EXPECT_NEAR(c.num(0, "runout [m]"), 0.8, kTol);
  EXPECT_NEAR(c.num(0, "height [m]"), 0.1, kTol);

  // Run-out towards -x from x = 2.5, height along a given up.
  make_function("runOut", "bodies (left); origin (2.5 0); direction (-2 0); up (0 -1);",
                make_context(dir.path(), "neg"))
      ->execute(layout(0, 0));
  c = read_csv(dir.path() / "postProcessing" / "neg" / "runOut.csv");
  EXPECT_NEAR(c.num(0, "runout [m]"), 2.4, kTol);
  EXPECT_NEAR(c.num(0, "height [m]"), 0.0, kTol);
}

TEST(RunOut, ThreeDimensions) {
  TempDir dir;
  auto ctx = make_context(dir.path(), "f3", 3);
  Snapshot s;
  s.dimension = 3;
  auto a = make_body("left", 0, {{0.1, 0.2, 0.3}, {0.4, 0.1, 0.7}}, {0, 1});
  add_field(a, "velocity", 3, {0, 0, 1, 1, 2, 2}, "m/s");
  add_field(a, "mass", 1, {2, 1}, "kg");
  s.bodies = {a};
  make_function("runOut", "", ctx)->execute(s);
  const Csv c = read_csv(dir.path() / "postProcessing" / "f3" / "runOut.csv");
  EXPECT_EQ(c.header.at(3), "kinetic_energy [J]");
  EXPECT_NEAR(c.num(0, "runout [m]"), 0.4, kTol);
  EXPECT_NEAR(c.num(0, "height [m]"), 0.7, kTol);  // up = +z
  EXPECT_NEAR(c.num(0, "kinetic_energy [J]"), 0.5 * (2 * 1 + 1 * 9), kTol);
  EXPECT_NEAR(c.num(0, "mean_velocity_z [m/s]"), 4.0 / 3.0, kTol);
  EXPECT_NEAR(c.num(0, "max_speed [m/s]"), 3.0, kTol);
}

TEST(RunOut, RestartKeepsEarlierRowsFreshRunReplaces) {
  TempDir dir;
  const fs::path file = dir.path() / "postProcessing" / "front" / "runOut.csv";
  {
    auto f = make_function("runOut", "", make_context(dir.path(), "front"));
    for (int i = 0; i < 3; ++i) f->execute(layout(0.1 * i, i));
  }
  ASSERT_EQ(read_csv(file).rows.size(), 3u);
  {
    auto ctx = make_context(dir.path(), "front");
    ctx.start_time = 0.15;
    auto f = make_function("runOut", "", ctx);
    f->execute(layout(0.15, 15));
  }
  Csv c = read_csv(file);
  ASSERT_EQ(c.rows.size(), 3u);
  EXPECT_NEAR(c.num(1, "time [s]"), 0.1, kTol);
  EXPECT_NEAR(c.num(2, "time [s]"), 0.15, kTol);
  {
    auto f = make_function("runOut", "", make_context(dir.path(), "front"));
    // Nothing written before the first execution (a user error in a plugin constructed
    // later must leave the case as it was); then the file is replaced.
    EXPECT_EQ(read_csv(file).rows.size(), 3u);
    f->execute(layout(0, 0));
    EXPECT_EQ(read_csv(file).rows.size(), 1u);  // flushed at once
  }
}

TEST(RunOut, InputErrors) {
  TempDir dir;
  auto ctx = make_context(dir.path(), "e");
  EXPECT_THROW(make_function("runOut", "heightWindow (1 0);", ctx), scree::InputError);
  {
    // A zero direction: reported by the spec's validation (scree --check, located) and by
    // the constructor.
    auto d = scree::Dictionary::parse("type runOut; direction (0 0);", "test");
    const auto& e = runtime().registry().get(scree::PluginKind::functionObject, "runOut", {});
    std::vector<scree::InputError> errors;
    scree::validate(*e.spec, d, errors, 2);
    ASSERT_EQ(errors.size(), 1u);
    EXPECT_NE(std::string(errors[0].what()).find("test:1:14: direction: expected a non-zero direction"),
              std::string::npos)
        << errors[0].what();
    EXPECT_THROW(e.function_object(d, ctx), scree::InputError);
  }
  try {
    make_function("runOut", "bodies (rigt);", ctx);
    ADD_FAILURE() << "expected an InputError";
  } catch (const scree::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("did you mean 'right'"), std::string::npos) << e.what();
  }
  // The output directory cannot be created: a clear error before the run.
  std::ofstream(dir.path() / "postProcessing") << "a file in the way";
  try {
    make_function("runOut", "", ctx);
    ADD_FAILURE() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("runOut 'e'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("postProcessing"), std::string::npos) << e.what();
  }
}

// Points that left the grid (a run where 97 of 1,600 points had left
// reported 1,600 particles and a front stuck at the grid's edge). Particle 3 of "left"
// (x = 2, the front) is lost at the second execution: every function object leaves it out,
// and says how many were lost in lostPoints.csv, which a run without lost points never
// writes (its other files are as before).
TEST(LostPoints, LeftOutOfEveryStatisticAndCounted) {
  TempDir dir;
  auto front_ctx = make_context(dir.path(), "front");
  auto energy_ctx = make_context(dir.path(), "energy");
  auto front = make_function("runOut", "bodies (left); origin (0.1 0);", front_ctx);
  auto energy = make_function("energies", "bodies (left); origin (0 0.1);", energy_ctx);
  for (auto* f : {front.get(), energy.get()}) f->execute(layout(0.0, 0));
  EXPECT_FALSE(fs::exists(dir.path() / "postProcessing" / "front" / "lostPoints.csv")) << "none lost yet";
  Snapshot s = layout(0.5, 7);
  s.bodies[0].lost = {0, 0, 0, 1};
  s.bodies[1].lost = {1};  // not a selected body: not counted
  for (auto* f : {front.get(), energy.get()}) f->execute(s);
  const Csv c = read_csv(dir.path() / "postProcessing" / "front" / "runOut.csv");
  ASSERT_EQ(c.rows.size(), 2u);
  EXPECT_NEAR(c.num(0, "runout [m]"), 1.9, kTol);
  EXPECT_NEAR(c.num(1, "runout [m]"), 0.8, kTol);  // the furthest point still on the grid, x = 0.9
  EXPECT_EQ(c.num(1, "particles [-]"), 3);
  EXPECT_EQ(c.num(1, "mass [kg/m]"), 6);
  EXPECT_NEAR(c.num(1, "kinetic_energy [J/m]"), 7.5, kTol);  // 1/2 (1*1 + 2*4 + 3*2)
  for (const char* name : {"front", "energy"}) {
    const Csv lost = read_csv(dir.path() / "postProcessing" / name / "lostPoints.csv");
    const std::vector<std::string> header = {"time [s]", "lost points [-]"};
    EXPECT_EQ(lost.header, header) << name;
    ASSERT_EQ(lost.rows.size(), 1u) << name << ": a row from the first execution with a lost point";
    EXPECT_EQ(lost.num(0, "time [s]"), 0.5);
    EXPECT_EQ(lost.num(0, "lost points [-]"), 1) << name;
  }
  const Csv e = read_csv(dir.path() / "postProcessing" / "energy" / "energies.csv");
  EXPECT_NEAR(e.num(1, "kinetic [J/m]"), 7.5, kTol);
  EXPECT_NEAR(e.num(1, "potential [J/m]"), 9.81 * 0.3, kTol);  // m g (y - 0.1) of the three left: 0.3

  // A fresh run in the same place removes the earlier run's count.
  auto again = make_function("runOut", "bodies (left); origin (0.1 0);", front_ctx);
  again->execute(layout(0.0, 0));
  EXPECT_FALSE(fs::exists(dir.path() / "postProcessing" / "front" / "lostPoints.csv"));
}

TEST(Energies, KineticAndPotential) {
  TempDir dir;
  auto ctx = make_context(dir.path(), "energy");
  make_function("energies", "bodies (left); origin (0 0.1);", ctx)->execute(layout(1, 1));
  const Csv c = read_csv(dir.path() / "postProcessing" / "energy" / "energies.csv");
  const std::vector<std::string> header = {"time [s]", "kinetic [J/m]", "potential [J/m]", "total [J/m]"};
  EXPECT_EQ(c.header, header);
  // m g (y - 0.1): 1*(-0.1) + 2*0.2 + 3*0 + 4*(-0.05) = 0.1
  const double pot = 9.81 * 0.1;
  EXPECT_NEAR(c.num(0, "kinetic [J/m]"), 57.5, kTol);
  EXPECT_NEAR(c.num(0, "potential [J/m]"), pot, kTol);
  EXPECT_NEAR(c.num(0, "total [J/m]"), 57.5 + pot, kTol);
}

namespace {

/// Probes: body left ids 10 11 12, body right ids 20 21; `moved` reorders the particles
/// and moves them (particle 10 ends where 11 was picked).
Snapshot probe_snapshot(double time, std::int64_t step, bool moved, bool drop20 = false) {
  Snapshot s;
  s.time = time;
  s.step = step;
  std::vector<std::array<double, 3>> pl = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  std::vector<std::int64_t> il = {10, 11, 12};
  std::vector<std::array<double, 3>> pr = {{5, 5, 0}, {6, 6, 0}};
  std::vector<std::int64_t> ir = {20, 21};
  if (moved) {
    pl = {{0, 1.2, 0}, {1.5, 0.2, 0}, {0.9, 0.1, 0}};  // ids 12, 11, 10
    il = {12, 11, 10};
    pr = {{6, 6, 0}, {5.5, 5, 0}};
    ir = {21, 20};
  }
  if (drop20) {
    pr = {{6, 6, 0}};
    ir = {21};
  }
  auto a = make_body("left", 0, pl, il);
  auto b = make_body("right", 1, pr, ir);
  for (auto* body : {&a, &b}) {
    std::vector<double> p, v, st;
    for (auto id : body->id) {
      p.push_back(id * 10 + time);
      v.insert(v.end(), {static_cast<double>(id), -static_cast<double>(id), 0});
      for (int c = 0; c < 6; ++c) st.push_back(id * 100 + c);
    }
    add_field(*body, "pressure", 1, p, "Pa");
    add_field(*body, "velocity", 3, v, "m/s");
    add_field(*body, "stress", 6, st, "Pa");
  }
  add_field(b, "granularTemperature", 1, std::vector<double>(b.n, 0.5), "m^2/s^2");
  s.bodies = {a, b};
  return s;
}

}  // namespace

TEST(ParticleProbes, PicksNearestAndTracksById) {
  TempDir dir;
  auto ctx = make_context(dir.path(), "probes");
  auto f = make_function("particleProbes",
                         "points ((0.9 0.1) (5.2 5.1)); names (A B); fields (pressure velocity stress granularTemperature);",
                         ctx);
  testing::internal::CaptureStderr();
  f->execute(probe_snapshot(0, 0, false));
  f->execute(probe_snapshot(0.1, 1, true));
  f->execute(probe_snapshot(0.1, 1, true));  // same step: no row
  f->execute(probe_snapshot(0.2, 2, true, true));
  const std::string err = testing::internal::GetCapturedStderr();
  // granularTemperature is not a field of A's body: reported; B's particle vanished.
  EXPECT_NE(err.find("granularTemperature"), std::string::npos) << err;
  EXPECT_NE(err.find("no longer"), std::string::npos) << err;

  const fs::path pp = dir.path() / "postProcessing" / "probes";
  const Csv sel = read_csv(pp / "selection.csv");
  ASSERT_EQ(sel.rows.size(), 2u);
  EXPECT_EQ(sel.rows[0][0], "A");
  EXPECT_EQ(sel.rows[0][sel.col("particle_id [-]")], "11");
  EXPECT_EQ(sel.rows[0][sel.col("body")], "left");
  EXPECT_NEAR(sel.num(0, "distance [m]"), std::hypot(0.1, 0.1), kTol);
  EXPECT_EQ(sel.rows[1][sel.col("particle_id [-]")], "20");

  const Csv a = read_csv(pp / "A.csv");
  const std::vector<std::string> header = {"time [s]",       "x [m]",          "y [m]",          "pressure [Pa]",
                                           "velocity_x [m/s]", "velocity_y [m/s]", "stress_xx [Pa]", "stress_yy [Pa]",
                                           "stress_zz [Pa]", "stress_xy [Pa]"};
  EXPECT_EQ(a.header, header);
  ASSERT_EQ(a.rows.size(), 3u);
  // Still particle 11 after the reordering, though particle 10 now sits on the point.
  EXPECT_NEAR(a.num(1, "x [m]"), 1.5, kTol);
  EXPECT_NEAR(a.num(1, "y [m]"), 0.2, kTol);
  EXPECT_NEAR(a.num(1, "pressure [Pa]"), 110.1, kTol);
  EXPECT_NEAR(a.num(1, "velocity_y [m/s]"), -11, kTol);
  EXPECT_NEAR(a.num(1, "stress_xy [Pa]"), 1103, kTol);

  const Csv b = read_csv(pp / "B.csv");
  ASSERT_EQ(b.rows.size(), 3u);
  EXPECT_EQ(b.header.back(), "granularTemperature [m^2/s^2]");
  EXPECT_NEAR(b.num(1, "x [m]"), 5.5, kTol);
  EXPECT_EQ(b.rows[2][b.col("x [m]")], "nan");
}

TEST(ParticleProbes, DefaultFieldsAndNames) {
  TempDir dir;
  auto ctx = make_context(dir.path(), "p");
  auto f = make_function("particleProbes", "points ((0 0)); bodies (right);", ctx);
  f->execute(probe_snapshot(0, 0, false));
  const Csv c = read_csv(dir.path() / "postProcessing" / "p" / "probe0.csv");
  // Every field of the body, expanded; the particle of body right nearest (0 0).
  const std::vector<std::string> header = {
      "time [s]",       "x [m]",          "y [m]",          "pressure [Pa]",  "velocity_x [m/s]",
      "velocity_y [m/s]", "stress_xx [Pa]", "stress_yy [Pa]", "stress_zz [Pa]", "stress_xy [Pa]",
      "granularTemperature [m^2/s^2]"};
  EXPECT_EQ(c.header, header);
  EXPECT_NEAR(c.num(0, "x [m]"), 5, kTol);
}

TEST(ParticleProbes, InputErrors) {
  TempDir dir;
  auto ctx = make_context(dir.path(), "p");
  EXPECT_THROW(make_function("particleProbes", "points ((0 0) (1 1)); names (A);", ctx), scree::InputError);
  EXPECT_THROW(make_function("particleProbes", "points ((0 0) (1 1)); names (A A);", ctx), scree::InputError);
  EXPECT_THROW(make_function("particleProbes", "points ((0 0 0));", ctx), scree::InputError);
  EXPECT_THROW(make_function("particleProbes", "points ((0 zero));", ctx), scree::InputError);
  EXPECT_THROW(make_function("particleProbes", "points ();", ctx), scree::InputError);
}

TEST(SurfaceProfile, BinsAndFiles) {
  TempDir dir;
  auto ctx = make_context(dir.path(), "profile");  // cell size 0.1: the default bin width
  Snapshot s;
  s.time = 0.5;
  auto a = make_body("left", 0, {{0.05, 0.2, 0}, {0.07, 0.5, 0}, {0.26, 0.1, 0}}, {0, 1, 2});
  s.bodies = {a};
  make_function("surfaceProfile", "", ctx)->execute(s);
  const fs::path pp = dir.path() / "postProcessing" / "profile";
  Csv c = read_csv(pp / "0.5.csv");
  const std::vector<std::string> header = {"distance [m]", "height [m]", "particles [-]"};
  EXPECT_EQ(c.header, header);
  ASSERT_EQ(c.rows.size(), 3u);
  EXPECT_NEAR(c.num(0, "distance [m]"), 0.05, kTol);
  EXPECT_NEAR(c.num(0, "height [m]"), 0.5, kTol);
  EXPECT_EQ(c.num(0, "particles [-]"), 2);
  EXPECT_EQ(c.rows[1][1], "nan");
  EXPECT_EQ(c.num(1, "particles [-]"), 0);
  EXPECT_NEAR(c.num(2, "height [m]"), 0.1, kTol);

  // A fixed range with narrower bins; a fresh run removes the earlier time files.
  s.time = 0.25;
  make_function("surfaceProfile", "binWidth 0.05; range (0 0.4);", ctx)->execute(s);
  EXPECT_FALSE(fs::exists(pp / "0.5.csv"));
  c = read_csv(pp / "0.25.csv");
  ASSERT_EQ(c.rows.size(), 8u);
  EXPECT_NEAR(c.num(1, "distance [m]"), 0.075, kTol);
  EXPECT_NEAR(c.num(1, "height [m]"), 0.5, kTol);
  EXPECT_NEAR(c.num(5, "height [m]"), 0.1, kTol);
  EXPECT_EQ(c.rows[7][1], "nan");
  EXPECT_TRUE(temporaries(pp).empty());
}
