// SplitTuner: for KernelPolicy::split = automatic on CUDA, decides chunk by chunk which way
// the stress pass runs: as one kernel (way 0); split, an elastic-only kernel and then the
// whole update over the points it defers (way 1); or split with the deferred updates in
// turns, persistent warps that take the deferred points from a queue and then a pass that
// scatters them (way 2, KernelPolicy::refill, for a material whose update runs in turns).
//
// After a chunk of steps run one way it records the rate; every kTrialSeconds of run time
// it runs one chunk another way (each of the others in turn), then keeps whichever was
// faster by 3% (so that noise does not flip it back and forth). A way not yet timed is
// tried at once. The flow changes which is faster (the share of plastic points, and so the
// deferred points' work), hence the repeated trials; a trial costs at most a chunk (~0.5 s)
// in ~10 s. The split gains for problems of many waves of threads and loses for those under
// a wave or two, where its kernels run one after the other; the updates in turns gain where
// the deferred points outnumber the lanes of a wave, and cost a launch more where they do not.
#pragma once

#include <cstdint>

#include "scree/core/config.hpp"

namespace scree {

class SCREE_API SplitTuner {
 public:
  static constexpr double kTrialSeconds = 10;  ///< run time between trials [s]
  static constexpr double kMargin = 1.03;      ///< a trial's way must win by this factor
  static constexpr int kMaxWays = 3;

  /// ways: how many of the ways above the pass can run (2, or 3 with the updates in turns).
  explicit SplitTuner(int ways = 2) : ways_(ways) {}

  /// After a chunk of n steps that took `seconds`, run the way `way`, at run time `wall`:
  /// the way of the next chunk.
  int next(int way, std::int64_t n, double seconds, double wall);

 private:
  int ways_;
  int trial_from_ = -1;             // the way a running trial left (-1: none running)
  int turn_ = 0;                    // which of the other ways the next trial tries
  double rate_[kMaxWays] = {0, 0, 0};  // steps per second, last measured, per way (0: never)
  double next_trial_wall_ = 0;      // run time at which the next trial starts
};

}  // namespace scree
