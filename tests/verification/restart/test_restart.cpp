// Restart from a checkpoint (case/checkpoint.hpp) reaches the state of the run that was
// never interrupted: bit for bit on one CPU thread (the same operations on the same
// numbers in the same order), and every file the writers and function objects wrote is
// the same, byte for byte, as the uninterrupted run's.
//
// Each case runs once to its end with every checkpoint kept (run A). A copy of its
// directory, results included, loses the checkpoints after a mid time and gets what a
// killed run leaves (a frame written past the checkpoint but not listed in the .pvd, a
// writer's hidden temporary): the restart from the mid checkpoint must repair the series
// and end in A's state. The cases cover every update scheme, the three shape functions,
// FLIP and APIC, a material with state variables, particle sorting between checkpoints,
// the adaptive step, a boundary law, function objects and the two-phase formulation.
// On the GPU (label gpu) the atomics' order of additions differs from run to run: the
// restart is compared with the run-to-run spread of two uninterrupted runs.
#include <gtest/gtest.h>

#include <csignal>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include "scree/case/checkpoint.hpp"
#include "scree/solver/simulation.hpp"
#include "scree_test.hpp"

namespace fs = std::filesystem;

namespace scree::test {
namespace {

/// Writes every 1/32 s (binary-exact times, so that an endTime on a write time is the same
/// number in every run), every checkpoint kept.
const char* const kControl =
    "endTime 0.25; deltaT 1e-3; adjustTimeStep yes; maxCo 0.4; writeInterval 0.03125; checkpointKeep 100; "
    "writers { particles { type vtk; directory VTK; } } "
    "functions { front { type runOut; } probe { type particleProbes; points ((0.05 0.05)); "
    "executeControl timeStep; executeInterval 7; } }";

struct Variant {
  const char* name;
  std::string schemes, materials, bodies, boundaries, grid = "dimension 2; lower (0 0); upper (1.2 0.3); cellSize 0.02;";
};

std::vector<Variant> variants() {
  const std::string block = "b { material m; velocity (3 0); region { type rectangle; lower (0.1 0); upper (0.3 0.06); } }";
  return {
      {"slidingBlockUSF", "updateScheme USF; sortInterval 7;", "m { type linearElastic; E 2e5; nu 0.3; rho 1000; }",
       block, "floor { type friction; face yMin; coefficient 0.5; }"},
      {"sandMUSLgimp", "updateScheme MUSL; shapeFunction gimp; sortInterval 5;",
       "m { type simsand; particleDensity 2650; referenceBulkModulus 120; poissonRatio 0.2; atmosphericPressure "
       "101300; elasticExponent 0.5; criticalFrictionAngle 30; referenceCriticalVoidRatio 0.977; criticalStateLambda "
       "0.0596; criticalStateXi 0.365; dilatancyConstant 0.7; plasticModulusConstant 0.0044; peakStrengthExponent "
       "2.4; phaseTransformationExponent 2.9; initialVoidRatio 0.95; }",
       "b { material m; region { type rectangle; lower (0 0); upper (0.2 0.2); } initialStress { type geostatic; "
       "K0 0.5; } }",
       "floor { type fixed; face yMin; } wall { type slip; face xMin; }"},
      {"granularUSLbsplineAPIC", "updateScheme USL; shapeFunction bspline2; transfer APIC; sortInterval 11;",
       "m { type phaseTransition; particleDensity 2650; diameter 1.25e-3; voidRatioSd 0.62; solidFractionM 0.4; "
       "restitutionCoefficient 0.6; particleFriction 0.2; initialGranularTemperature 1e-12; referenceBulkModulus "
       "120; poissonRatio 0.2; atmosphericPressure 101300; elasticExponent 0.5; criticalFrictionAngle 19.8; "
       "referenceCriticalVoidRatio 0.977; criticalStateLambda 0.0596; criticalStateXi 0.365; dilatancyConstant 0.7; "
       "plasticModulusConstant 0.0044; peakStrengthExponent 2.4; phaseTransformationExponent 2.9; initialVoidRatio "
       "0.95; }",
       "b { material m; region { type rectangle; lower (0 0); upper (0.2 0.2); } initialStress { type geostatic; "
       "K0 0.5; } }",
       "floor { type friction; face yMin; coefficient 0.4; } wall { type slip; face xMin; }"},
      {"twoPhaseRainGimp", "updateScheme USL; shapeFunction gimp;", "m { type linearElastic; E 5e6; nu 0; rho 2700; }",
       "column { material m; region { type rectangle; lower (0 0); upper (0.1 1); } initialStress { type geostatic; "
       "K0 0; } twoPhase { porosity 0.33; liquidDensity 1000; liquidBulkModulus 2e8; viscosity 1e-3; "
       "hydraulicConductivity 2e-4; retention { type vanGenuchten; p0 22295; lambda 0.671; Smin 0.23; Smax 1; } "
       "permeability { type mualemVanGenuchten; } initialPorePressure { type hydrostatic; waterTable 0.3; } } }",
       "base { type fixed; face yMin; } left { type slip; face xMin; } right { type slip; face xMax; } "
       "rain { type rainfall; box { min (-1 1.0); max (1 1.2); } intensity 5e-4; unit m/s; }",
       "dimension 2; lower (0 0); upper (0.1 1.2); cellSize 0.05;"},
      // A pond on the surface (rainfall's pondingDepth) carried by the points from step to
      // step: a saturated column draining through its base under a rain of twice K_sat.
      {"twoPhasePond", "updateScheme USL;", "m { type linearElastic; E 5e7; nu 0; rho 2650; }",
       "column { material m; region { type rectangle; lower (0 0); upper (0.05 0.5); } initialStress { type "
       "geostatic; K0 0; } twoPhase { porosity 0.4; liquidBulkModulus 2e6; hydraulicConductivity 0.1; "
       "initialPorePressure { type hydrostatic; waterTable 0.5; } } }",
       "base { type fixed; face yMin; drained yes; } waterTable { type porePressure; min (-1 -1); max (1 0.01); "
       "waterTable 0; } left { type slip; face xMin; } right { type slip; face xMax; } "
       "rain { type rainfall; box { min (-1 0.45); max (1 0.6); } intensity 0.2; pondingDepth 1; }",
       "dimension 2; lower (0 0); upper (0.05 0.6); cellSize 0.05;"},
  };
}

void write_case(const TempCase& tc, const Variant& v, const std::string& control = kControl) {
  write_case_files(tc, CaseFiles{control, v.schemes, v.grid, "value (0 -9.81);", v.materials, v.bodies, v.boundaries});
}

RunOptions with_output() {
  RunOptions o = options(1);  // one thread: the order of the additions is fixed
  o.output = true;
  return o;
}

/// Run the case in `dir` to its end (from `restart` when given); its final state.
Snapshot run(const fs::path& dir, const fs::path& restart = {}) {
  Case c = Case::read(dir, runtime());
  RunOptions o = with_output();
  o.restart = restart;
  Simulation sim(c, runtime(), o);
  sim.run();
  return sim.snapshot();
}

std::string read_all(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Every regular file under `dir` relative to it (checkpoints/ aside), sorted.
std::vector<fs::path> files_under(const fs::path& dir) {
  std::vector<fs::path> out;
  for (const auto& de : fs::recursive_directory_iterator(dir)) {
    const fs::path rel = fs::relative(de.path(), dir);
    if (de.is_regular_file() && *rel.begin() != "checkpoints") out.push_back(rel);
  }
  std::sort(out.begin(), out.end());
  return out;
}

/// The two cases' results: the same files (series, frames, CSVs), byte for byte on the CPU.
void expect_same_files(const fs::path& a, const fs::path& b, const std::string& after) {
  const auto fa = files_under(a), fb = files_under(b);
  EXPECT_EQ(fa, fb);
  if (test_device() == Device::cpu)
    for (const auto& f : fa)
      if (std::find(fb.begin(), fb.end(), f) != fb.end())
        EXPECT_TRUE(read_all(a / f) == read_all(b / f)) << f << " differs after " << after;
}

/// The largest difference of any value of any field (0 when bit for bit the same;
/// relative to the field's largest magnitude).
double largest_difference(const Snapshot& a, const Snapshot& b) {
  double worst = 0;
  EXPECT_EQ(a.bodies.size(), b.bodies.size());
  for (std::size_t k = 0; k < std::min(a.bodies.size(), b.bodies.size()); ++k) {
    const BodySnapshot &A = a.bodies[k], &B = b.bodies[k];
    EXPECT_EQ(A.n, B.n);
    if (A.n != B.n) return 1;
    EXPECT_EQ(A.id, B.id) << "particle order of body " << A.name;
    for (const FieldData& fa : A.fields) {
      const FieldData* fb = B.find(fa.name.c_str());
      EXPECT_NE(fb, nullptr) << fa.name;
      if (!fb) continue;
      double scale = 0, diff = 0;
      for (std::size_t i = 0; i < fa.values.size(); ++i) {
        scale = std::max(scale, std::fabs(fa.values[i]));
        if (std::memcmp(&fa.values[i], &fb->values[i], sizeof(Real)) != 0)
          diff = std::max(diff, std::isfinite(fa.values[i] - fb->values[i]) ? std::fabs(fa.values[i] - fb->values[i])
                                                                             : 1e300);
      }
      if (diff > 0) worst = std::max(worst, diff / std::max(scale, 1e-300));
      if (test_device() == Device::cpu)
        EXPECT_EQ(diff, 0.0) << "field " << fa.name << " of body " << A.name << " differs after the restart";
    }
  }
  return worst;
}

class Restart : public ::testing::TestWithParam<Variant> {};

TEST_P(Restart, FromAMidCheckpointEndsInTheUninterruptedState) {
  const Variant& v = GetParam();
  TempCase a(std::string("restartA_") + v.name);
  write_case(a, v);
  const Snapshot final_a = run(a.dir());
  const auto checkpoints = list_checkpoints(a.dir());
  // Every 8th write of 8 to endTime 0.25: the 7 write times after 0 and endTime itself.
  ASSERT_EQ(checkpoints.size(), 8u) << "one checkpoint per write time after t = 0";
  EXPECT_EQ(checkpoints.back().filename(), "0.25.ckpt");

  // B: a copy of A's directory, as a run killed after t = 0.1875 would have left it.
  TempCase b(std::string("restartB_") + v.name);
  fs::copy(a.dir(), b.dir(), fs::copy_options::recursive | fs::copy_options::overwrite_existing);
  for (const auto& f : list_checkpoints(b.dir()))
    if (f.filename() != "0.09375.ckpt" && f.filename() != "0.125.ckpt") fs::remove(f);
  std::ofstream(b.dir() / "VTK" / ".particles_6.vtp.tmp123_4") << "half a file";
  std::ofstream(b.dir() / "VTK" / "particles_99.vtp") << "a frame written but never listed";
  const auto newest = list_checkpoints(b.dir()).back();
  ASSERT_EQ(newest.filename(), "0.125.ckpt");
  const Snapshot final_b = run(b.dir(), newest);
  EXPECT_EQ(final_a.time, final_b.time);
  EXPECT_EQ(final_a.step, final_b.step) << "steps that advanced the clock";
  if (const FieldData* pond = final_a.bodies.at(0).find("pond"); pond && std::string(v.name) == "twoPhasePond") {
    double ponded = 0;
    for (double x : pond->values) ponded += x;
    EXPECT_GT(ponded, 1) << "kg/m: no pond stood on the column (the restart's test of it needs one)";
  }
  const double diff = largest_difference(final_a, final_b);
  std::cout << "[ restart ] " << v.name << ": largest relative difference " << diff << " after the restart\n";
  EXPECT_FALSE(fs::exists(b.dir() / "VTK" / ".particles_6.vtp.tmp123_4")) << "a killed run's temporary";
  EXPECT_FALSE(fs::exists(b.dir() / "VTK" / "particles_99.vtp")) << "a frame past the checkpoint, never listed";

  expect_same_files(a.dir(), b.dir(), "the restart");
  if (test_device() == Device::cuda) {
    // The GPU's own spread: a second uninterrupted run.
    TempCase c(std::string("restartC_") + v.name);
    write_case(c, v);
    const double spread = largest_difference(final_a, run(c.dir()));
    std::cout << "[ restart ] " << v.name << ": two uninterrupted GPU runs differ by " << spread << "\n";
    EXPECT_LE(diff, std::max(100 * spread, 1e-9)) << "the restart against the GPU's run-to-run spread";
  }
}

INSTANTIATE_TEST_SUITE_P(Cases, Restart, ::testing::ValuesIn(variants()),
                         [](const ::testing::TestParamInfo<Variant>& i) { return std::string(i.param.name); });

// A run stopped by a signal (request_stop: scree's SIGINT/SIGTERM handler) at the end of
// every chunk of steps, and restarted from the checkpoint each stop writes, writes the
// uninterrupted run's files byte for byte. The chunks end at every event: the write times
// (with checkpointInterval 2, every other one is no checkpoint time of the schedule) and
// the probe's steps (executeControl timeStep), so each stop lands on a time at which
// something was due; a stop's own frame and rows at its time are replaced by the restart.
// Also: a later endTime continued from the checkpoint of the earlier one (the frame at
// the old endTime must stay).
TEST(RestartSignal, StoppedAtEveryEventAndRestartedWritesTheUninterruptedFiles) {
  const Variant v = variants().front();
  std::string control = kControl;
  control += " checkpointInterval 2; progressInterval 1000000;";
  TempCase a("restartSignalA");
  write_case(a, v, control);
  const Snapshot whole = run(a.dir());

  TempCase b("restartSignalB");
  write_case(b, v, control);
  int stops = 0, at_write_times = 0;
  fs::path from;
  for (;;) {
    request_stop(SIGTERM);
    try {
      run(b.dir(), from);
      break;  // reached endTime
    } catch (const RunInterrupted&) {
      ++stops;
    }
    from = list_checkpoints(b.dir()).back();
    double t = 0;
    ASSERT_TRUE(checkpoint_time(from, t));
    const double writes = t / 0.03125;
    if (std::fabs(writes - std::round(writes)) < 1e-6 && std::llround(writes) % 2 == 1) ++at_write_times;
    ASSERT_LT(stops, 2000) << "the stops do not advance the run";
  }
  request_stop(0);
  std::cout << "[ restart ] " << stops << " stops by signal, " << at_write_times
            << " of them at a write time that is not a checkpoint time of the schedule\n";
  EXPECT_GE(at_write_times, 3);
  expect_same_files(a.dir(), b.dir(), "the stops and restarts");
}

TEST(RestartEndTime, ALaterEndTimeKeepsTheFramesOfTheEarlierOne) {
  const Variant v = variants().front();
  TempCase a("restartEndFilesA");
  write_case(a, v);
  run(a.dir());
  TempCase b("restartEndFilesB");
  std::string control = kControl;
  control.replace(control.find("endTime 0.25"), 12, "endTime 0.15625");  // the 5th write time
  write_case(b, v, control);
  run(b.dir());
  write_case(b, v);  // endTime 0.25 again
  run(b.dir(), list_checkpoints(b.dir()).back());
  expect_same_files(a.dir(), b.dir(), "the continuation");
}

// A run to an earlier endTime, continued with a later one, is the run to the later one.
TEST(RestartEndTime, ALaterEndTimeContinuesTheRun) {
  const Variant v = variants().front();
  TempCase a("restartEndA");
  write_case(a, v);
  const Snapshot whole = run(a.dir());
  TempCase b("restartEndB");
  std::string control = kControl;
  control.replace(control.find("endTime 0.25"), 12, "endTime 0.15625");  // the 5th write time
  write_case(b, v, control);
  const Snapshot part = run(b.dir());
  EXPECT_EQ(part.time, 0.15625);
  write_case(b, v);  // endTime 0.25 again
  const auto newest = list_checkpoints(b.dir()).back();
  EXPECT_EQ(newest.filename(), "0.15625.ckpt") << "the checkpoint of endTime";
  const Snapshot continued = run(b.dir(), newest);
  EXPECT_EQ(continued.time, whole.time);
  largest_difference(whole, continued);
}

// The step after a write time follows the CFL condition. A write flushes the last step's
// gather, which in USL holds its stress update and so the signal speed the next step is
// sized by; the host's copy of the clock did not have it, wrote itself back for the next
// target, and the step after every write of an adaptive USL run was maxDeltaT (here 14
// times the CFL step; a restart, whose clock came from the device, differed from the
// uninterrupted run). Writing 16 times as often must then not save steps: each write may
// add one landing step, no more, and none may be missed.
TEST(WriteTimes, TheStepAfterAWriteFollowsTheCflCondition) {
  auto steps = [](const char* interval) {
    TempCase tc("cflAfterWrite");
    Variant v = variants().front();
    v.schemes = "updateScheme USL; shapeFunction bspline2; transfer APIC;";
    std::string control = kControl;
    control.replace(control.find("writeInterval 0.03125"), 21, std::string("writeInterval ") + interval);
    write_case(tc, v, control);
    return run(tc.dir()).step;
  };
  const std::int64_t few = steps("0.125"), many = steps("0.0078125");  // 2 and 32 writes
  std::cout << "[ restart ] steps with 2 writes: " << few << ", with 32: " << many << "\n";
  EXPECT_GE(many, few) << "writing more often saved steps: a step after a write was larger than the CFL step";
  EXPECT_LE(many, few + 32) << "more than one extra (landing) step per write";
}

// A fresh run removes an earlier run's checkpoints; a checkpoint that does not fit the case
// (another particle count) is an error naming the file before anything runs.
/// The case of `tc` rewritten as `v` and continued from the checkpoint `from` to its end
/// (accept_changes: RunOptions's); throws what the restart refuses, before it writes.
void continue_as(const TempCase& tc, const Variant& v, const fs::path& from, bool accept_changes) {
  write_case(tc, v);
  Case c = Case::read(tc.dir(), runtime());
  RunOptions o = with_output();
  o.restart = from;
  o.accept_changes = accept_changes;
  Simulation sim(c, runtime(), o);
  sim.run();
}

// A restart after a change of the case's physics (a material's E doubled) is refused,
// naming the entry, before anything is written; with accept_changes it runs, and the frames
// and rows written before the checkpoint's time stay as they were.
TEST(RestartErrors, AChangeOfPhysicsIsRefusedNamingTheEntry) {
  const Variant v = variants().front();
  TempCase a("restartPhysics");
  write_case(a, v);
  run(a.dir());
  const auto checkpoints = list_checkpoints(a.dir());
  ASSERT_GE(checkpoints.size(), 4u);
  const fs::path mid = checkpoints[checkpoints.size() / 2];
  double t_mid = 0;
  ASSERT_TRUE(checkpoint_time(mid, t_mid));
  const std::string pvd_before = read_all(a.dir() / "VTK" / "particles.pvd");
  const std::string frame1 = read_all(a.dir() / "VTK" / "particles_1.vtp");
  Variant changed = v;
  changed.materials = "m { type linearElastic; E 4e5; nu 0.3; rho 1000; }";
  try {
    continue_as(a, changed, mid, false);
    FAIL() << "a restart with a changed material was accepted";
  } catch (const InputErrors& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("materialProperties"), std::string::npos) << m;
    EXPECT_NE(m.find("'m.E' changed"), std::string::npos) << m;
    EXPECT_NE(m.find("2e5 then, 4e5 now"), std::string::npos) << "the values: " << m;
    EXPECT_NE(m.find("--accept-changes"), std::string::npos) << m;
    EXPECT_EQ(m.find("bodies"), std::string::npos) << "only the changed entry: " << m;
  }
  EXPECT_EQ(read_all(a.dir() / "VTK" / "particles.pvd"), pvd_before) << "the refused restart wrote";
  continue_as(a, changed, mid, true);
  EXPECT_EQ(read_all(a.dir() / "VTK" / "particles_1.vtp"), frame1) << "a frame before the checkpoint was rewritten";
  // The series: every entry before the checkpoint's time as it was.
  const std::string pvd_after = read_all(a.dir() / "VTK" / "particles.pvd");
  std::ostringstream t;
  t << "timestep=\"" << t_mid << "\"";
  const auto cut_before = pvd_before.find(t.str()), cut_after = pvd_after.find(t.str());
  ASSERT_NE(cut_before, std::string::npos);
  ASSERT_NE(cut_after, std::string::npos);
  EXPECT_EQ(pvd_before.substr(0, cut_before), pvd_after.substr(0, cut_after));
}

TEST(RestartErrors, ACheckpointOfAnotherCaseIsRefused) {
  const Variant v = variants().front();
  TempCase a("restartErrA");
  write_case(a, v);
  run(a.dir());
  const auto newest = list_checkpoints(a.dir()).back();
  Variant other = v;
  other.bodies = "b { material m; velocity (3 0); region { type rectangle; lower (0.1 0); upper (0.3 0.1); } }";
  try {
    continue_as(a, other, newest, true);  // past the physics check: the state itself does not fit
    FAIL() << "a checkpoint with another particle count was accepted";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("constant/bodies"), std::string::npos) << m;
    EXPECT_NE(m.find(newest.filename().string()), std::string::npos) << m;
    EXPECT_NE(m.find("particles"), std::string::npos) << m;
  }
  // A corrupt checkpoint: one byte changed.
  {
    std::fstream f(newest, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(100);
    f.put('\x7f');
  }
  try {
    (void)Checkpoint::read(newest);
    FAIL() << "a corrupt checkpoint was read";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("checksum"), std::string::npos) << e.what();
  }
  // A run from startTime clears the old checkpoints before it writes its own.
  std::string control = kControl;
  control.replace(control.find("endTime 0.25"), 12, "endTime 0.03125");
  write_case(a, v, control);
  Case fresh = Case::read(a.dir(), runtime());
  {
    RunOptions o2 = with_output();
    Simulation sim(fresh, runtime(), o2);
    EXPECT_TRUE(list_checkpoints(a.dir()).empty()) << "an earlier run's checkpoints outlived a fresh start";
  }
}

}  // namespace
}  // namespace scree::test

SCREE_TEST_MAIN()
