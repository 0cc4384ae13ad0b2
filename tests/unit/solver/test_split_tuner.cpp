// SplitTuner (split_tuner.hpp): which way the stress pass runs, chunk by chunk, from the
// rates it measured. Fed chunks whose duration is a known function of the way, it must
// time every way once, settle on the fastest, hold it between trials, and leave a way only
// for one that is faster by its margin.
#include <gtest/gtest.h>

#include <vector>

#include "split_tuner.hpp"

namespace scree::test {
namespace {

/// How many of the last n chunks ran `way`.
int last_at(const std::vector<int>& w, std::size_t n, int way) {
  int k = 0;
  for (std::size_t c = w.size() - n; c < w.size(); ++c) k += w[c] == way;
  return k;
}

/// Runs `chunks` chunks of 100 steps from `way`, each taking seconds[way] of run time;
/// returns the way of every chunk.
std::vector<int> drive(SplitTuner& t, int way, const std::vector<double>& seconds, int chunks, double& wall) {
  std::vector<int> ways;
  for (int c = 0; c < chunks; ++c) {
    ways.push_back(way);
    wall += seconds[way];
    way = t.next(way, 100, seconds[way], wall);
  }
  return ways;
}

TEST(SplitTuner, TimesEveryWayOnceThenKeepsTheFastest) {
  SplitTuner t(3);
  double wall = 0;
  // way 2 fastest, 1 next, 0 slowest; start at 1: the untimed ways are tried first, in order
  const std::vector<int> w = drive(t, 1, {0.5, 0.3, 0.2}, 12, wall);
  EXPECT_EQ(w[0], 1);
  EXPECT_EQ(w[1], 0);  // untimed, slower: back to 1
  EXPECT_EQ(w[2], 1);
  EXPECT_EQ(w[3], 2);  // untimed, faster: kept
  for (std::size_t c = 4; c < w.size(); ++c) EXPECT_EQ(w[c], 2) << "chunk " << c;  // no trial within 10 s
}

TEST(SplitTuner, TriesTheOtherWaysInTurnAndLeavesOnlyForAClearGain) {
  SplitTuner t(3);
  double wall = 0;
  // way 0 faster by 2% only than way 2: within the margin, the tuner stays at 2, trying
  // each other way for one chunk every 10 s of run time, in turn
  std::vector<double> s = {0.98, 2.0, 1.0};
  std::vector<int> w = drive(t, 2, s, 60, wall);
  int trials0 = 0, trials1 = 0;
  for (std::size_t c = 1; c < w.size(); ++c) {
    trials0 += w[c] == 0;
    trials1 += w[c] == 1;
  }
  EXPECT_GE(trials0, 3);
  EXPECT_GE(trials1, 2);
  EXPECT_LE(trials0 + trials1, 8);  // ~62 s of run time: the two first trials, then one per 10 s
  EXPECT_GE(last_at(w, 10, 2), 9);
  // the flow changes: way 0 now clearly faster; a trial of it (within two trials) moves there
  s = {0.5, 2.0, 1.0};
  w = drive(t, 2, s, 60, wall);
  EXPECT_GE(last_at(w, 20, 0), 19);
}

TEST(SplitTuner, TwoWaysAlternateTrials) {
  SplitTuner t(2);
  double wall = 0;
  const std::vector<int> w = drive(t, 1, {0.3, 0.5}, 40, wall);
  EXPECT_EQ(w[0], 1);
  EXPECT_EQ(w[1], 0);  // the untimed way tried at once, and kept (faster)
  EXPECT_GE(last_at(w, 30, 0), 29);
  for (int v : w) EXPECT_LT(v, 2);
}

TEST(SplitTuner, ShortChunksDoNotCount) {
  SplitTuner t(3);
  // chunks under 50 steps time the host: no decision from them
  for (int c = 0; c < 10; ++c) EXPECT_EQ(t.next(2, 10, 1.0, c), 2);
}

}  // namespace
}  // namespace scree::test
