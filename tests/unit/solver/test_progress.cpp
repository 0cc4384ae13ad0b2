// The progress line (framework/src/solver/progress.hpp): its durations stay readable for
// any elapsed time and ETA, however absurd.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <sstream>
#include <string>

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

}  // namespace
}  // namespace scree
