// How many threads the next step runs on, when the scene leaves it to the
// solver ("threads": 0, the default): all the process may use while they are
// faster than one, one while the machine is so busy that they are not
// (docs/design.md, "Threads").
//
// On a machine whose cores other processes keep busy, a thread of a team is
// now and then descheduled for a whole time slice (milliseconds) while the
// others wait for it at the step's barriers; one thread never waits. Which
// is faster is measured, not guessed: the solver reports each step's wall
// time, and now and then a short probe runs the other choice. The first
// probe comes after kFirstInterval steps; probes become twice as rare
// each time they lose (up to kLongestInterval steps apart) and
// frequent again when the step time moves the way a change of load moves it
// (all threads slower, or one thread faster), so a load that comes is
// noticed within a few dozen steps, one that goes within kLongestInterval. Results do not depend on the choice
// (bitwise, method.md §5).
#pragma once

namespace loosehair {

class ThreadChoice {
 public:
  static constexpr int kProbeSteps = 2;
  static constexpr int kFirstInterval = 4;  // steps before the first probe
  static constexpr int kShortestInterval = 16;
  static constexpr int kLongestInterval = 1024;

  /// Chooses between `most` threads and one (`most` >= 1).
  explicit ThreadChoice(int most);

  /// The thread count for the next step.
  int next() const;
  /// The wall time of the step that ran with next() threads.
  void record(double seconds);

  int most() const { return most_; }

 private:
  int most_;
  bool many_ = true;         // the current choice: most_ threads (else one)
  double mean_ = 0;          // running mean step time of the current choice
  double decided_mean_ = 0;  // mean_ when the current choice was last confirmed
  int since_probe_ = 0, interval_ = kFirstInterval;
  int probing_ = 0;  // probe steps left (> 0: the other choice runs)
  double probe_sum_ = 0;
};

}  // namespace loosehair
