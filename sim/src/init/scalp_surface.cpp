#include "init/scalp_surface.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace loosehair {

SphereCapScalp::SphereCapScalp(glm::vec3 center, float radius, float cap_angle)
    : center_(center), radius_(radius), cap_angle_(cap_angle) {}

glm::vec3 SphereCapScalp::normal(glm::vec2 uv) const {
  // concentric square -> disc; u = 1 right (+x), v = 0 front (+z), as on
  // a mesh scalp, so that styles and length maps mean the same on both
  const double a = 2.0 * uv.x - 1.0, b = 1.0 - 2.0 * uv.y;
  const double quarter = std::numbers::pi / 4.0;
  double rho = 0, phi = 0;
  if (a == 0.0 && b == 0.0) {
    rho = 0;
  } else if (std::abs(a) > std::abs(b)) {
    rho = a;
    phi = quarter * (b / a);
  } else {
    rho = b;
    phi = 2.0 * quarter - quarter * (a / b);
  }
  const double dx = rho * std::cos(phi), dz = rho * std::sin(phi);
  const double radial = std::sqrt(dx * dx + dz * dz);
  // disc -> cap, equal area
  const double cos_theta = 1.0 - radial * radial * (1.0 - std::cos(static_cast<double>(cap_angle_)));
  const double sin_theta = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
  const double ex = radial > 0 ? dx / radial : 1.0, ez = radial > 0 ? dz / radial : 0.0;
  return glm::vec3(glm::dvec3(sin_theta * ex, cos_theta, sin_theta * ez));
}

glm::vec3 SphereCapScalp::point(glm::vec2 uv) const { return center_ + radius_ * normal(uv); }

glm::vec2 SphereCapScalp::sampleByArea(Random& rng) const {
  return {static_cast<float>(rng.uniform()), static_cast<float>(rng.uniform())};
}

double SphereCapScalp::area() const {
  return 2.0 * std::numbers::pi * radius_ * radius_ * (1.0 - std::cos(static_cast<double>(cap_angle_)));
}

}  // namespace loosehair
