#include "loosehair/body.hpp"

#include <glm/geometric.hpp>

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

}  // namespace loosehair
