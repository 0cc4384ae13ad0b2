// The progress line (framework/src/solver/progress.hpp): its durations stay readable for
// any elapsed time and ETA, however absurd.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <string>
#include <thread>

#include "progress.hpp"

namespace scree {
namespace {

TEST(Progress, DurationsAreMinutesOrHoursAndSaturateBeyondAHundredDays) {
  EXPECT_EQ(format_duration(0), "0:00");
  EXPECT_EQ(format_duration(59.6), "1:00");
  EXPECT_EQ(format_duration(3725), "1:02:05");
  EXPECT_EQ(format_duration(-1), "--:--");
  EXPECT_EQ(format_duration(std::nan("")), "--:--");
  EXPECT_EQ(format_duration(99 * 86400.0), "2376:00:00");
  EXPECT_EQ(format_duration(100 * 86400.0), ">100 days");
  EXPECT_EQ(format_duration(1e30), ">100 days");
  EXPECT_EQ(format_duration(std::numeric_limits<double>::max()), ">100 days");
  EXPECT_EQ(format_duration(std::numeric_limits<double>::infinity()), "--:--");
}

// A run that barely advances (deltaT 1e-30 before it was refused) showed
// "ETA -153722867280912930:-8": the ETA overflowed the conversion to an integer.
TEST(Progress, TheEtaOfARunThatBarelyAdvancesSaturates) {
  std::ostringstream log;
  Progress p(log, false, 0.0, 3.0);
  p.report(1e-25, 1000000, true);
  const std::string line = log.str();
  EXPECT_NE(line.find("ETA >100 days"), std::string::npos) << line;
  EXPECT_EQ(line.find("ETA -"), std::string::npos) << line;
}

// A run restarted at step 10000 and t = 1.5 s of a 3 s run: its rate is of its own 100
// steps in at least 0.2 s, at most 500 steps/s (the whole run's 10100 steps would give 50
// times that), and its ETA is its own wall time per simulated second times the 1.4 s left:
// at least 0.2 s x 14 = 2.8 s (the whole run's fraction done would give 0.9 x 0.2 s).
TEST(Progress, ARestartedRunCountsItsOwnStepsAndTime) {
  std::ostringstream log;
  Progress p(log, false, 0.0, 3.0);
  p.start(1.5, 10000);
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  p.report(1.6, 10100, true);
  const std::string line = log.str();
  std::istringstream is(line.substr(line.find("step")));
  std::string word;
  long long step = 0;
  double rate = 0;
  is >> word >> step >> rate;
  EXPECT_EQ(step, 10100) << line;
  EXPECT_GT(rate, 0) << line;
  EXPECT_LE(rate, 500.0) << line;
  const auto at = line.find("ETA ");
  ASSERT_NE(at, std::string::npos) << line;
  int m = 0, sec = 0;
  ASSERT_EQ(std::sscanf(line.c_str() + at + 4, "%d:%d", &m, &sec), 2) << line;
  EXPECT_GE(60 * m + sec, 2) << line;
  EXPECT_NE(line.find("53.3%"), std::string::npos) << "the percentage is of the whole run: " << line;
}

}  // namespace
}  // namespace scree
