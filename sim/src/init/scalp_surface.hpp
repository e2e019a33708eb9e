// A scalp parameterised over the unit square D = [0,1]^2 (method.md §6.1):
// f^-1(u, v) gives a point and normal. Implementations: the analytic sphere
// cap here; the harmonic map of a trimmed head mesh later.
#pragma once

#include "util/random.hpp"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace loosehair {

class ScalpSurface {
 public:
  virtual ~ScalpSurface() = default;
  virtual glm::vec3 point(glm::vec2 uv) const = 0;
  virtual glm::vec3 normal(glm::vec2 uv) const = 0;
  /// A parameter point drawn uniformly with respect to surface area.
  virtual glm::vec2 sampleByArea(Random& rng) const = 0;
  /// Surface area (m^2).
  virtual double area() const = 0;
};

/// The cap of a sphere within `cap_angle` (radians) of the crown (+Y).
/// (u, v) -> disc by the concentric (Shirley-Chiu) map, disc -> cap by the
/// equal-area azimuthal map 1 - cos(theta) = rho^2 (1 - cos(cap_angle)), so
/// uniform (u, v) is uniform in area.
class SphereCapScalp final : public ScalpSurface {
 public:
  SphereCapScalp(glm::vec3 center, float radius, float cap_angle);
  glm::vec3 point(glm::vec2 uv) const override;
  glm::vec3 normal(glm::vec2 uv) const override;
  glm::vec2 sampleByArea(Random& rng) const override;
  double area() const override;

 private:
  glm::vec3 center_;
  float radius_, cap_angle_;
};

}  // namespace loosehair
