// A head moved by hand while the hair simulates (the viewer's head drag and
// its shake and nod buttons; method.md §5 inertial forces from the live
// trajectory). The simulation reads a keyframed trajectory whose keys are
// the poses asked for, placed a few frames ahead of the simulation time, so
// every key a step's kinematics depend on exists before the step is taken.
// The keys, written as a scene's "keyframes" motion, give the same
// trajectory again: a run replayed by `loosehair simulate` gives the same
// bits.
#pragma once

#include "loosehair/head_motion.hpp"

#include <cstdint>
#include <vector>

namespace loosehair {

class LiveHead {
 public:
  /// Keys `lead` frames ahead: Catmull-Rom needs the key after the next one,
  /// and the kinematics' central differences look a little past the end of
  /// a frame, hence 3.
  static constexpr int kLead = 3;

  /// Starts at rest at `rest` for a simulation of `frame_rate` frames a
  /// second. Throws std::invalid_argument for a rate that is not finite and
  /// positive.
  explicit LiveHead(double frame_rate, const HeadKeyframe& rest = {});

  /// The time of frame n (n / frame_rate, as the keys store it).
  double frameTime(std::int64_t n) const;

  /// Called once at the start of each simulated frame n (0, 1, 2, ... in
  /// order): the pose wanted now becomes the key of frame n + kLead (its
  /// time is set here). Throws std::logic_error when frames are skipped or
  /// repeated.
  void beginFrame(std::int64_t n, HeadKeyframe wanted);

  /// The trajectory so far: valid for every time up to the end of the last
  /// frame begun.
  const HeadTrajectory& trajectory() const { return trajectory_; }
  const std::vector<HeadKeyframe>& keys() const { return keys_; }
  /// The pose of the newest key (what the head is heading for).
  const HeadKeyframe& latest() const { return keys_.back(); }

 private:
  double frame_rate_;
  std::int64_t next_frame_ = 0;
  std::vector<HeadKeyframe> keys_;
  HeadTrajectory trajectory_;
};

/// The pose that turns the head by `euler_deg` (yaw, pitch, roll) about
/// `pivot` (head frame at rest, e.g. the base of the neck) and then moves
/// it by `offset`: the keyframe translation is pivot - R pivot + offset.
HeadKeyframe turnAbout(const glm::dvec3& pivot, const glm::dvec3& euler_deg, const glm::dvec3& offset);

}  // namespace loosehair
