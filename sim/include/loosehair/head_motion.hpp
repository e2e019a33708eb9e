// Prescribed rigid head trajectories (method.md §5 "Head motion and inertia").
// A trajectory only has to give the pose at any time; velocities and
// accelerations are taken by central differences in double precision, so any
// smooth trajectory (procedural or keyframed) gets its inertial forces.
#pragma once

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include <string>
#include <vector>

namespace loosehair {

struct HeadPose {
  glm::dmat3 rotation{1.0};  // R(t): head frame -> world
  glm::dvec3 center{0.0};    // c(t): head frame origin in the world (m)
};

/// What the solver needs of the head at time t, all in double precision.
struct HeadKinematics {
  HeadPose pose;
  glm::dvec3 velocity{0.0};              // c'(t), world (m/s)
  glm::dvec3 acceleration{0.0};          // c''(t), world (m/s^2)
  glm::dvec3 angular_velocity{0.0};      // omega, head frame (rad/s)
  glm::dvec3 angular_acceleration{0.0};  // alpha, head frame (rad/s^2)
};

struct HeadKeyframe {
  double time = 0.0;            // s
  glm::dvec3 euler_deg{0.0};    // yaw (about +Y), pitch (about +X), roll (about +Z), degrees
  glm::dvec3 translation{0.0};  // m
};

class HeadTrajectory {
 public:
  enum class Kind { Still, Shake, Nod, Keyframes };

  /// The head does not move.
  static HeadTrajectory still();
  /// Turn left and right about the head's up axis (+Y): yaw(t) =
  /// amplitude * sin(2 pi f (t - start)) for `cycles` periods after `start`,
  /// with a smooth envelope over the first and last period so that it starts
  /// and stops without jerk, then rest.
  static HeadTrajectory shake(double amplitude_rad, double frequency_hz, double cycles, double start = 0.0);
  /// The same as shake about the head's side axis (+X).
  static HeadTrajectory nod(double amplitude_rad, double frequency_hz, double cycles, double start = 0.0);
  /// Catmull-Rom interpolation of keyframes (sorted by time, at least two);
  /// the pose is held before the first and after the last.
  static HeadTrajectory keyframes(std::vector<HeadKeyframe> keys);

  Kind kind() const { return kind_; }
  HeadPose pose(double t) const;
  /// Yaw (about +Y), pitch (about +X) and roll (about +Z) at t (rad).
  glm::dvec3 angles(double t) const { return eulerAt(t); }
  HeadKinematics kinematics(double t) const;
  /// Time after which the head is at rest for good (0 for still).
  double endTime() const;

 private:
  glm::dvec3 eulerAt(double t) const;
  glm::dvec3 translationAt(double t) const;

  Kind kind_ = Kind::Still;
  double amplitude_ = 0.0, frequency_ = 0.0, cycles_ = 0.0, start_ = 0.0;
  std::vector<HeadKeyframe> keys_;
};

/// R = Ry(yaw) * Rx(pitch) * Rz(roll), angles in radians.
glm::dmat3 rotationFromEuler(const glm::dvec3& yaw_pitch_roll);

}  // namespace loosehair
