// SplitTuner (see split_tuner.hpp).
#include "split_tuner.hpp"

namespace scree {

int SplitTuner::next(int way, std::int64_t n, double seconds, double wall) {
  // Chunks of a few steps (the first ones, or cut short by an event) time the host, not
  // the kernels.
  if (n < 50 || seconds <= 0) return way;
  rate_[way] = static_cast<double>(n) / seconds;
  if (trial_from_ >= 0) {
    const int from = trial_from_;
    trial_from_ = -1;
    // keep the trial's way only if it beat the one it left clearly
    const int keep = rate_[way] < kMargin * rate_[from] ? from : way;
    bool untimed = false;
    for (int w = 0; w < ways_; ++w) untimed = untimed || rate_[w] == 0;
    next_trial_wall_ = untimed ? wall : wall + kTrialSeconds;
    return keep;
  }
  if (wall < next_trial_wall_) return way;
  int trial = -1;
  for (int w = 0; w < ways_ && trial < 0; ++w)
    if (w != way && rate_[w] == 0) trial = w;
  if (trial < 0) trial = (way + 1 + turn_++ % (ways_ - 1)) % ways_;
  trial_from_ = way;
  return trial;
}

}  // namespace scree
