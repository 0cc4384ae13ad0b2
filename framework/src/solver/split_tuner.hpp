// SplitTuner: for KernelPolicy::split = automatic on CUDA, decides chunk by chunk whether
// the stress pass runs split (an elastic-only kernel, then the whole update over the
// points it defers) or as one kernel.
//
// After a chunk of steps run one way it records the rate; every kTrialSeconds of run time
// it runs one chunk the other way, then keeps whichever was faster by 3% (so that noise
// does not flip it back and forth). The flow changes which is faster (the share of plastic
// points, and so the second kernel's work), hence the repeated trials; a trial costs at
// most a chunk (~0.5 s) in ~10 s. The split gains for problems of many waves of threads
// and loses for those under a wave or two, where its two kernels run one after the other.
#pragma once

#include <cstdint>

namespace scree {

class SplitTuner {
 public:
  static constexpr double kTrialSeconds = 10;  ///< run time between trials [s]
  static constexpr double kMargin = 1.03;      ///< a trial's way must win by this factor

  /// After a chunk of n steps that took `seconds`, run split (`split`) now, at run time
  /// `wall`: whether the next chunk runs split.
  bool next(bool split, std::int64_t n, double seconds, double wall);

 private:
  bool trial_ = false;          // this chunk runs the other way, to time it
  double rate_[2] = {0, 0};     // steps per second, last measured split off [0] and on [1]
  double next_trial_wall_ = 0;  // run time at which the next trial starts
};

}  // namespace scree
