#include "util/thread_choice.hpp"

#include <algorithm>
#include <cmath>

namespace loosehair {

ThreadChoice::ThreadChoice(int most) : most_(std::max(1, most)), many_(most_ > 1) {}

int ThreadChoice::next() const {
  const bool many = probing_ > 0 ? !many_ : many_;
  return many ? most_ : 1;
}

void ThreadChoice::record(double seconds) {
  if (most_ == 1 || !(seconds >= 0) || !std::isfinite(seconds)) return;
  if (probing_ > 0) {
    probe_sum_ += seconds;
    if (--probing_ > 0) return;
    const double probe_mean = probe_sum_ / kProbeSteps;
    if (probe_mean < 0.8 * mean_) {  // clearly faster (a noisy step or two is not): switch
      many_ = !many_;
      mean_ = probe_mean;
      interval_ = kShortestInterval;
    } else {
      interval_ = std::min(2 * interval_, kLongestInterval);
    }
    decided_mean_ = mean_;
    since_probe_ = 0;
    return;
  }
  constexpr double kWeight = 1.0 / 16;  // about the last 16 steps
  mean_ = mean_ > 0 ? mean_ + kWeight * (seconds - mean_) : seconds;
  if (decided_mean_ <= 0) decided_mean_ = mean_;
  // The step time moved away from the last decision's the way a change of
  // load moves it (all threads slower: other processes came; one thread
  // faster: they went), so probe again soon. One thread on a busy machine
  // varies a lot from step to step, and slower steps of it say nothing new.
  if (many_ ? mean_ > 1.5 * decided_mean_ : mean_ < decided_mean_ / 1.5)
    interval_ = std::min(interval_, kShortestInterval);
  if (++since_probe_ >= interval_) {
    probing_ = kProbeSteps;
    probe_sum_ = 0;
  }
}

}  // namespace loosehair
