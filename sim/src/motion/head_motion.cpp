#include "loosehair/head_motion.hpp"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace loosehair {
namespace {

// C2 ramp 0 -> 1 on [0, 1] (6x^5 - 15x^4 + 10x^3): the head starts and stops
// with zero velocity and acceleration, so the inertial forces have no jumps.
double smootherStep(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x * x * x * (x * (6.0 * x - 15.0) + 10.0);
}

glm::dmat3 axisRotation(const glm::dvec3& axis, double angle) {
  return glm::dmat3(glm::rotate(glm::dmat4(1.0), angle, axis));
}

glm::dvec3 skewToVector(const glm::dmat3& m) {  // glm is column-major: m[col][row]
  return {0.5 * (m[1][2] - m[2][1]), 0.5 * (m[2][0] - m[0][2]), 0.5 * (m[0][1] - m[1][0])};
}

// Cubic Hermite through the keys' values with Catmull-Rom tangents (zero at
// the ends), held constant outside the keys' times.
glm::dvec3 interpolateKeys(const std::vector<HeadKeyframe>& k, double t, glm::dvec3 HeadKeyframe::*value) {
  if (t <= k.front().time) return k.front().*value;
  if (t >= k.back().time) return k.back().*value;
  const std::size_t i = static_cast<std::size_t>(
      std::upper_bound(k.begin(), k.end(), t, [](double v, const HeadKeyframe& key) { return v < key.time; }) -
      k.begin() - 1);
  auto tangent = [&](std::size_t j) {
    if (j == 0 || j + 1 >= k.size()) return glm::dvec3(0.0);
    return (k[j + 1].*value - k[j - 1].*value) / (k[j + 1].time - k[j - 1].time);
  };
  const double h = k[i + 1].time - k[i].time, x = (t - k[i].time) / h;
  const double h00 = 2 * x * x * x - 3 * x * x + 1, h10 = x * x * x - 2 * x * x + x, h01 = -2 * x * x * x + 3 * x * x,
               h11 = x * x * x - x * x;
  return h00 * k[i].*value + h10 * h * tangent(i) + h01 * k[i + 1].*value + h11 * h * tangent(i + 1);
}

}  // namespace

glm::dmat3 rotationFromEuler(const glm::dvec3& ypr) {
  return axisRotation({0, 1, 0}, ypr.x) * axisRotation({1, 0, 0}, ypr.y) * axisRotation({0, 0, 1}, ypr.z);
}

HeadTrajectory HeadTrajectory::still() { return HeadTrajectory(); }

HeadTrajectory HeadTrajectory::shake(double amplitude_rad, double frequency_hz, double cycles, double start) {
  if (!std::isfinite(amplitude_rad) || !(frequency_hz > 0) || !std::isfinite(frequency_hz) || !(cycles > 0) ||
      !std::isfinite(cycles) || !std::isfinite(start))
    throw std::invalid_argument("head shake needs a finite amplitude, positive frequency and cycles");
  HeadTrajectory h;
  h.kind_ = Kind::Shake;
  h.amplitude_ = amplitude_rad;
  h.frequency_ = frequency_hz;
  h.cycles_ = cycles;
  h.start_ = start;
  return h;
}

HeadTrajectory HeadTrajectory::nod(double amplitude_rad, double frequency_hz, double cycles, double start) {
  HeadTrajectory h = shake(amplitude_rad, frequency_hz, cycles, start);
  h.kind_ = Kind::Nod;
  return h;
}

HeadTrajectory HeadTrajectory::keyframes(std::vector<HeadKeyframe> keys) {
  if (keys.size() < 2) throw std::invalid_argument("head keyframes: at least two are needed");
  for (std::size_t k = 0; k < keys.size(); ++k) {
    const auto& key = keys[k];
    if (!std::isfinite(key.time) || !std::isfinite(key.euler_deg.x) || !std::isfinite(key.euler_deg.y) ||
        !std::isfinite(key.euler_deg.z) || !std::isfinite(key.translation.x) || !std::isfinite(key.translation.y) ||
        !std::isfinite(key.translation.z))
      throw std::invalid_argument("head keyframe " + std::to_string(k) + " has non-finite values");
    if (k > 0 && !(key.time > keys[k - 1].time))
      throw std::invalid_argument("head keyframe " + std::to_string(k) + ": times must increase strictly");
  }
  HeadTrajectory h;
  h.kind_ = Kind::Keyframes;
  h.keys_ = std::move(keys);
  return h;
}

double HeadTrajectory::endTime() const {
  switch (kind_) {
    case Kind::Still:
      return 0.0;
    case Kind::Shake:
    case Kind::Nod:
      return start_ + cycles_ / frequency_;
    case Kind::Keyframes:
      return keys_.back().time;
  }
  return 0.0;
}

glm::dvec3 HeadTrajectory::eulerAt(double t) const {
  switch (kind_) {
    case Kind::Still:
      return glm::dvec3(0.0);
    case Kind::Shake:
    case Kind::Nod: {
      const double period = 1.0 / frequency_, duration = cycles_ * period;
      const double tau = t - start_;
      if (tau <= 0.0 || tau >= duration) return glm::dvec3(0.0);
      const double envelope = smootherStep(tau / period) * smootherStep((duration - tau) / period);
      const double angle = amplitude_ * envelope * std::sin(2.0 * std::numbers::pi * frequency_ * tau);
      return kind_ == Kind::Shake ? glm::dvec3(angle, 0, 0) : glm::dvec3(0, angle, 0);
    }
    case Kind::Keyframes:
      break;
  }
  return glm::radians(interpolateKeys(keys_, t, &HeadKeyframe::euler_deg));
}

glm::dvec3 HeadTrajectory::translationAt(double t) const {
  if (kind_ != Kind::Keyframes) return glm::dvec3(0.0);
  return interpolateKeys(keys_, t, &HeadKeyframe::translation);
}

HeadPose HeadTrajectory::pose(double t) const {
  HeadPose p;
  p.rotation = rotationFromEuler(eulerAt(t));
  p.center = translationAt(t);
  return p;
}

HeadKinematics HeadTrajectory::kinematics(double t) const {
  HeadKinematics k;
  k.pose = pose(t);
  if (kind_ == Kind::Still) return k;
  constexpr double d = 1.0e-4;  // central differences in double precision
  const HeadPose pm = pose(t - d), pp = pose(t + d);
  k.velocity = (pp.center - pm.center) / (2 * d);
  k.acceleration = (pp.center - 2.0 * k.pose.center + pm.center) / (d * d);
  auto omegaAt = [&](double tt) {  // [omega]x = R^T dR/dt, body frame
    const glm::dmat3 r = rotationFromEuler(eulerAt(tt));
    const glm::dmat3 dr = (rotationFromEuler(eulerAt(tt + d)) - rotationFromEuler(eulerAt(tt - d))) / (2 * d);
    return skewToVector(glm::transpose(r) * dr);
  };
  k.angular_velocity = omegaAt(t);
  k.angular_acceleration = (omegaAt(t + d) - omegaAt(t - d)) / (2 * d);
  return k;
}

}  // namespace loosehair
