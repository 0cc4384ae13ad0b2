// The time-control unit (time/step_control.hpp, time/time_control.hpp), on its own: the
// rules the device applies after every step and the host applies between chunks.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "scree/time/time_control.hpp"

namespace scree {
namespace {

TimeSettings fixed_step(double dt, double end) {
  TimeSettings s;
  s.end_time = end;
  s.delta_t = dt;
  s.max_delta_t = dt;
  s.max_co = 0.5;
  return s;
}

TimeSettings adaptive_step(double dt, double end, double dt_max, double co) {
  TimeSettings s = fixed_step(dt, end);
  s.adjust_time_step = true;
  s.max_delta_t = dt_max;
  s.max_co = co;
  return s;
}

/// Run the device's per-step rule until the clock stops (dt = 0) on its target.
int run_to_target(StepControl& c, double speed) {
  int steps = 0, p = 0;
  while (c.dt[p] > 0) {
    c.max_speed[p] = speed;
    advance_clock(&c, p);
    p = 1 - p;
    ++steps;
  }
  return steps;
}

TEST(TimeControl, AFixedStepLandsExactlyOnTheTargetWithoutASliver) {
  TimeControl tc(fixed_step(0.3e-3, 1.0), 0.01);
  StepControl c = tc.initial();
  c.t_target = 1e-3;  // 3.33 steps: three of 0.3 ms and one of 0.1 ms
  const int steps = run_to_target(c, 0);
  const int p = steps % 2;
  EXPECT_EQ(steps, 4);
  EXPECT_DOUBLE_EQ(c.t[p], 1e-3);
  EXPECT_EQ(c.dt[p], 0) << "on the target the clock stops";
  EXPECT_EQ(c.steps_done, 4u);
  // A target a hair (below 1e-6 of a step) past a whole number of steps: no sliver step.
  StepControl d = tc.initial();
  d.t_target = 0.9e-3 * (1 + 1e-9);
  EXPECT_EQ(run_to_target(d, 0), 3);
}

TEST(TimeControl, TheAdaptiveStepIsCflTimesCellOverSignalSpeedCappedByMaxDeltaT) {
  const double h = 0.01, co = 0.5;
  TimeControl tc(adaptive_step(1e-3, 1.0, 2e-4, co), h);
  StepControl c = tc.initial();
  EXPECT_EQ(cfl_step(c, 100.0), co * h / 100.0);  // 5e-5 < maxDeltaT
  EXPECT_EQ(cfl_step(c, 1.0), 2e-4) << "capped by maxDeltaT";
  EXPECT_EQ(cfl_step(c, 0.0), 2e-4) << "nothing moves: maxDeltaT";
  c.max_speed[0] = 100;
  advance_clock(&c, 0);
  EXPECT_EQ(c.dt[1], co * h / 100.0);
  EXPECT_EQ(c.max_speed[0], 0) << "the slot is cleared for its next use";
}

TEST(TimeControl, TheFirstStepFollowsTheInitialSignalSpeed) {
  std::ostringstream log;
  const double h = 0.01;
  TimeControl adaptive(adaptive_step(1e-3, 1.0, 1e-3, 0.5), h);
  StepControl c = adaptive.initial();
  EXPECT_TRUE(adaptive.start(c, 1000.0, log));
  EXPECT_EQ(c.dt[0], 0.5 * (h / 1000.0));
  EXPECT_TRUE(log.str().empty());

  TimeControl fixed(fixed_step(1e-3, 1.0), h);  // h / c = 1e-5 s: deltaT is 100 times too long
  StepControl f = fixed.initial();
  EXPECT_FALSE(fixed.start(f, 1000.0, log));
  EXPECT_EQ(f.dt[0], 1e-3) << "a fixed step is the user's: reported, not changed";
  EXPECT_NE(log.str().find("exceeds the stable time step"), std::string::npos) << log.str();
}

TEST(TimeControl, RetargetingRederivesAStepThatStoppedOnTheOldTarget) {
  TimeControl tc(adaptive_step(1e-3, 1.0, 1e-3, 0.5), 0.01);
  StepControl c = tc.initial();
  c.t_target = 2e-3;
  const int p = run_to_target(c, 10.0) % 2;  // steps of 0.5 * 0.01 / 10 = 5e-4 s after the first
  ASSERT_DOUBLE_EQ(c.t[p], 2e-3);
  ASSERT_EQ(c.dt[p], 0);
  ASSERT_EQ(c.max_speed[1 - p], 0) << "the last step's slot is cleared";
  EXPECT_FALSE(tc.retarget(c, p, 2e-3)) << "the same target changes nothing";
  EXPECT_TRUE(tc.retarget(c, p, 2.2e-3));
  EXPECT_DOUBLE_EQ(c.dt[p], 2e-4) << "the remainder, shorter than the CFL step";
  EXPECT_TRUE(tc.retarget(c, p, 1.0));
  EXPECT_DOUBLE_EQ(c.dt[p], 2e-4) << "a step already under way is kept (the CFL rule acts after it)";
  c.dt[p] = 0;  // stopped on a target again
  EXPECT_TRUE(tc.retarget(c, p, 2.0));
  EXPECT_DOUBLE_EQ(c.dt[p], 5e-4) << "the CFL step of the last step's speed, not maxDeltaT (1e-3)";
  // Steps that idle on the target (dt = 0) and see no speed do not forget it.
  StepControl d = tc.initial();
  d.t_target = 2e-3;
  const int q = run_to_target(d, 10.0) % 2;
  advance_clock(&d, q);  // an idle step with max_speed 0
  EXPECT_TRUE(tc.retarget(d, 1 - q, 1.0));
  EXPECT_DOUBLE_EQ(d.dt[1 - q], 5e-4);
}

TEST(TimeControl, ChunksCoverTheTargetAndReachedToleratesRoundOff) {
  TimeControl fixed(fixed_step(1e-3, 1.0), 0.01);
  StepControl c = fixed.initial();
  EXPECT_EQ(fixed.steps_to(c, 0, 0.01), 10);
  EXPECT_EQ(fixed.steps_to(c, 0, 0.0105), 11);
  TimeControl adaptive(adaptive_step(1e-3, 1.0, 1e-3, 0.5), 0.01);
  EXPECT_EQ(adaptive.steps_to(adaptive.initial(), 0, 0.01), 11) << "one more: the adaptive step may shrink";
  EXPECT_TRUE(TimeControl::reached(1.0 - 1e-14, 1.0));
  EXPECT_FALSE(TimeControl::reached(1.0 - 1e-9, 1.0));
}

// A clock stopped on a target (dt = 0) asks for one step; a tiny step for at most kMaxSteps.
// Both were a float-to-int64 conversion of ~1e298 (undefined behaviour: UBSan stopped every
// run of a case in the sanitizer build; on x86 it happened to give 1).
TEST(TimeControl, StepsToAStoppedClockOrATinyStepStayInRange) {
  TimeControl adaptive(adaptive_step(1e-3, 1.0, 1e-3, 0.5), 0.01);
  StepControl c = adaptive.initial();
  c.dt[0] = 0;
  EXPECT_EQ(adaptive.steps_to(c, 0, 0.5), 1);
  c.dt[0] = 1e-290;
  EXPECT_EQ(adaptive.steps_to(c, 0, 0.5), static_cast<std::int64_t>(TimeControl::kMaxSteps));
}

TEST(TimeControl, TheWatchWarnsOnceWhenAFixedStepBecomesUnstable) {
  std::ostringstream log;
  TimeControl tc(fixed_step(1e-4, 1.0), 0.01);  // stable while c < 100 m/s
  int asked = 0;
  auto speed = [&] {
    ++asked;
    return 50.0 + 100.0 * (asked > 1);
  };
  tc.watch(6.0, 0.1, 1000, speed, log);  // 50 m/s: fine
  EXPECT_TRUE(log.str().empty());
  tc.watch(8.0, 0.2, 2000, speed, log);  // under 5 s of wall time since: not measured
  EXPECT_EQ(asked, 1);
  tc.watch(12.0, 0.3, 3000, speed, log);  // 150 m/s: h / c < deltaT
  EXPECT_NE(log.str().find("at t = 0.3 s (step 3000)"), std::string::npos) << log.str();
  const auto once = log.str();
  tc.watch(20.0, 0.4, 4000, speed, log);
  EXPECT_EQ(log.str(), once) << "warned once";
}

// deltaT 1e-30 with endTime 3: t + dt == t in double, and the run went on forever with
// no warning. A step the clock cannot add, or one needing more than 1e12 steps, is
// refused; the reason says which step would do.
TEST(TimeControl, AStepTheClockCannotAddOrThatNeedsMoreThan1e12StepsIsRefused) {
  const std::string never = TimeControl::step_problem(0, 3, 1e-30);
  EXPECT_NE(never.find("cannot advance the clock"), std::string::npos) << never;
  EXPECT_NE(never.find("at least 3e-12 s"), std::string::npos) << never;
  const std::string months = TimeControl::step_problem(0, 3, 1e-15);
  EXPECT_NE(months.find("needs 3e+15 steps"), std::string::npos) << months;
  EXPECT_EQ(TimeControl::step_problem(0, 3, 3e-12), "");  // exactly 1e12 steps
  EXPECT_NE(TimeControl::step_problem(0, 3, 2.9e-12), "");
  EXPECT_EQ(TimeControl::step_problem(0, 3, 2e-4), "");
  // Late in a long run the clock's resolution is what limits the step.
  EXPECT_NE(TimeControl::step_problem(1e9, 1e9 + 1, 1e-8).find("cannot advance the clock"), std::string::npos);
  // Settings built in code are checked too (a validated case never gets here).
  EXPECT_THROW(TimeControl(fixed_step(1e-30, 3.0), 0.01), std::invalid_argument);
  EXPECT_THROW(TimeControl(adaptive_step(1e-4, 3.0, 1e-30, 0.5), 0.01), std::invalid_argument);
  EXPECT_NO_THROW(TimeControl(adaptive_step(1e-30, 3.0, 1e-4, 0.5), 0.01)) << "only the first step is tiny";
}


// Health (step_control.hpp): a non-finite value, too many points off the grid or a step
// above stopCo stops the clock on the device for good, recording why and when; a healthy
// step is untouched.
TEST(TimeControl, AFailureFoundInAStepStopsTheClockAfterItForGood) {
  const double h = 0.01;
  TimeSettings s = fixed_step(1e-4, 1.0);
  s.stop_co = 2;
  TimeControl tc(s, h);
  // Healthy: Courant 1e-4 * 150 / 0.01 = 1.5 <= 2.
  StepControl c = tc.initial();
  c.max_speed[0] = 150;
  advance_clock(&c, 0);
  EXPECT_EQ(c.failure, 0u);
  EXPECT_EQ(c.dt[1], 1e-4);
  // Unstable: Courant 3 > 2 in step 1; the clock stops after it and stays stopped.
  c.max_speed[1] = 300;
  advance_clock(&c, 1);
  EXPECT_EQ(c.failure, unsigned(kFailUnstable));
  EXPECT_EQ(c.failed_step, 1u);
  EXPECT_DOUBLE_EQ(c.failed_co, 3.0);
  EXPECT_EQ(c.dt[0], 0) << "the clock stopped";
  advance_clock(&c, 0);
  EXPECT_EQ(c.dt[1], 0) << "and stays stopped";
  EXPECT_EQ(c.failed_step, 1u) << "the first failure is kept";
  EXPECT_EQ(c.steps_done, 2u);

  // A non-finite value found by a kernel (bad.count), and stopCo 0 checks nothing.
  s.stop_co = 0;
  TimeControl off(s, h);
  StepControl d = off.initial();
  d.max_speed[0] = 1e9;
  advance_clock(&d, 0);
  EXPECT_EQ(d.failure, 0u) << "stopCo 0: no check";
  d.bad.count = 1;
  advance_clock(&d, 1);
  EXPECT_EQ(d.failure, unsigned(kFailNonFinite));
  EXPECT_EQ(d.dt[0], 0);

  // Points off the grid: lost_stop of them stop it; 0 is no limit.
  StepControl e = off.initial();
  e.lost = 1000;
  advance_clock(&e, 0);
  EXPECT_EQ(e.failure, 0u) << "lost_stop 0: no limit";
  e.lost_stop = 1001;
  advance_clock(&e, 1);
  EXPECT_EQ(e.failure, 0u);
  e.lost = 1001;
  advance_clock(&e, 0);
  EXPECT_EQ(e.failure, unsigned(kFailLost));
  // A NaN signal speed is a failure too (not a comparison that quietly passes).
  s.stop_co = 2;
  TimeControl on(s, h);
  StepControl f = on.initial();
  f.max_speed[0] = std::nan("");
  advance_clock(&f, 0);
  EXPECT_EQ(f.failure, unsigned(kFailUnstable));
}

}  // namespace
}  // namespace scree
