#include "loosehair/live_head.hpp"

#include <glm/trigonometric.hpp>

#include <cmath>
#include <stdexcept>
#include <string>

namespace loosehair {

LiveHead::LiveHead(double frame_rate, const HeadKeyframe& rest) : frame_rate_(frame_rate) {
  if (!(std::isfinite(frame_rate) && frame_rate > 0.0))
    throw std::invalid_argument("live head: the frame rate must be finite and positive, got " +
                                std::to_string(frame_rate));
  // rest from frame 0 up to the first key an input can set
  for (int k = 0; k < kLead; ++k) {
    HeadKeyframe key = rest;
    key.time = frameTime(k);
    keys_.push_back(key);
  }
  trajectory_ = HeadTrajectory::keyframes(keys_);
}

double LiveHead::frameTime(std::int64_t n) const { return static_cast<double>(n) / frame_rate_; }

void LiveHead::beginFrame(std::int64_t n, HeadKeyframe wanted) {
  if (n != next_frame_)
    throw std::logic_error("live head: frame " + std::to_string(n) + " begun, expected " + std::to_string(next_frame_));
  ++next_frame_;
  wanted.time = frameTime(n + kLead);
  keys_.push_back(wanted);
  trajectory_ = HeadTrajectory::keyframes(keys_);
}

HeadKeyframe turnAbout(const glm::dvec3& pivot, const glm::dvec3& euler_deg, const glm::dvec3& offset) {
  HeadKeyframe k;
  k.euler_deg = euler_deg;
  const glm::dmat3 r = rotationFromEuler(glm::radians(euler_deg));
  k.translation = pivot - r * pivot + offset;
  return k;
}

}  // namespace loosehair
