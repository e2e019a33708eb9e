// Collision bodies as signed-distance functions (SPEC §5). Distances are
// negative inside. Queries are batched so that a body costs one virtual call
// per block of particles, not one per particle.
#pragma once

#include <glm/vec3.hpp>

#include <cstddef>

namespace loosehair {

class Body {
 public:
  virtual ~Body() = default;
  /// For each of the n points p[k] (in the body's frame): phi[k] = signed
  /// distance (m, negative inside), normal[k] = unit outward normal of the
  /// nearest surface point (gradient of phi).
  virtual void signedDistance(const glm::vec3* p, std::size_t n, float* phi,
                              glm::vec3* normal) const = 0;
};

/// An analytic sphere.
class SphereBody final : public Body {
 public:
  SphereBody(glm::vec3 center, float radius);
  void signedDistance(const glm::vec3* p, std::size_t n, float* phi,
                      glm::vec3* normal) const override;
  glm::vec3 center() const { return center_; }
  float radius() const { return radius_; }

 private:
  glm::vec3 center_;
  float radius_;
};

}  // namespace loosehair
