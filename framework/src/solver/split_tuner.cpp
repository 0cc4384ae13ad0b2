// SplitTuner (see split_tuner.hpp).
#include "split_tuner.hpp"

namespace scree {

bool SplitTuner::next(bool split, std::int64_t n, double seconds, double wall) {
  // Chunks of a few steps (the first ones, or cut short by an event) time the host, not
  // the kernels.
  if (n < 50 || seconds <= 0) return split;
  const int now = split ? 1 : 0;
  rate_[now] = static_cast<double>(n) / seconds;
  if (trial_) {
    trial_ = false;
    next_trial_wall_ = wall + kTrialSeconds;
    // keep the trial's way only if it beat the other clearly
    return rate_[now] < kMargin * rate_[1 - now] ? !split : split;
  }
  if (wall >= next_trial_wall_) {
    trial_ = true;
    return !split;
  }
  return split;
}

}  // namespace scree
