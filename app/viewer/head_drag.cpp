#include "viewer/head_drag.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace loosehair::viewer {

glm::dvec3 neckPivot(const TriangleMesh& head) {
  if (head.vertices.empty()) return glm::dvec3(0.0);
  glm::dvec3 lo(head.vertices.front()), hi(head.vertices.front());
  for (const glm::vec3& v : head.vertices) {
    lo = glm::min(lo, glm::dvec3(v));
    hi = glm::max(hi, glm::dvec3(v));
  }
  return {0.5 * (lo.x + hi.x), lo.y, 0.5 * (lo.z + hi.z)};
}

void HeadDrag::drag(double dx, double dy, bool move, const render::Camera& camera) {
  if (!move) {
    euler_deg_.x = std::clamp(euler_deg_.x + 0.3 * dx, -80.0, 80.0);
    euler_deg_.y = std::clamp(euler_deg_.y + 0.3 * dy, -80.0, 80.0);
    return;
  }
  const glm::dvec3 forward = glm::normalize(glm::dvec3(camera.target - camera.eye()));
  const glm::dvec3 right = glm::normalize(glm::cross(forward, glm::dvec3(0, 1, 0)));
  const glm::dvec3 up = glm::cross(right, forward);
  offset_ += 1e-3 * (dx * right - dy * up);
  const double len = glm::length(offset_);
  if (len > 0.3) offset_ *= 0.3 / len;
}

void HeadDrag::reset() {
  euler_deg_ = glm::dvec3(0.0);
  offset_ = glm::dvec3(0.0);
}

}  // namespace loosehair::viewer
