#include "loosehair/body.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace loosehair {

SphereBody::SphereBody(glm::vec3 center, float radius) : center_(center), radius_(radius) {
  if (!(radius > 0.0f)) throw std::invalid_argument("sphere radius must be positive");
}

void SphereBody::signedDistance(const glm::vec3* p, std::size_t n, float* phi,
                                glm::vec3* normal) const {
  for (std::size_t k = 0; k < n; ++k) {
    const glm::vec3 d = p[k] - center_;
    const float r = glm::length(d);
    phi[k] = r - radius_;
    normal[k] = r > 0.0f ? d / r : glm::vec3(0.0f, 1.0f, 0.0f);
  }
}

CapsuleBody::CapsuleBody(glm::vec3 a, glm::vec3 b, float radius) : a_(a), b_(b), radius_(radius) {
  if (!(radius > 0.0f) || !std::isfinite(radius)) throw std::invalid_argument("capsule radius must be positive");
}

void CapsuleBody::signedDistance(const glm::vec3* p, std::size_t n, float* phi,
                                 glm::vec3* normal) const {
  const glm::vec3 ab = b_ - a_;
  const float len2 = glm::dot(ab, ab);
  for (std::size_t k = 0; k < n; ++k) {
    const float t = len2 > 0.0f ? std::clamp(glm::dot(p[k] - a_, ab) / len2, 0.0f, 1.0f) : 0.0f;
    const glm::vec3 d = p[k] - (a_ + t * ab);
    const float r = glm::length(d);
    phi[k] = r - radius_;
    normal[k] = r > 0.0f ? d / r : glm::vec3(0.0f, 1.0f, 0.0f);
  }
}

void UnionBody::signedDistance(const glm::vec3* p, std::size_t n, float* phi,
                               glm::vec3* normal) const {
  for (std::size_t k = 0; k < n; ++k) {
    phi[k] = INFINITY;
    normal[k] = glm::vec3(0.0f, 1.0f, 0.0f);
  }
  std::vector<float> pb(n);
  std::vector<glm::vec3> nb(n);
  for (const auto& part : parts_) {
    part->signedDistance(p, n, pb.data(), nb.data());
    for (std::size_t k = 0; k < n; ++k)
      if (pb[k] < phi[k]) {
        phi[k] = pb[k];
        normal[k] = nb[k];
      }
  }
}

float UnionBody::roughError() const {
  float most = 0.0f;
  for (const auto& part : parts_) {
    const float e = part->roughError();
    if (!(e >= 0.0f)) return -1.0f;
    most = std::max(most, e);
  }
  return most;
}

}  // namespace loosehair
