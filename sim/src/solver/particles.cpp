#include "loosehair/particles.hpp"

#include <glm/geometric.hpp>

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace loosehair {

void Particles::resize(std::size_t n) {
  position.resize(n);
  velocity.resize(n);
  direction.resize(n);
  mass.resize(n);
  is_root.resize(n);
  uv.resize(n);
  arc_length.resize(n);
  root_point.resize(n);
}

Particles Particles::select(const std::vector<std::uint32_t>& which) const {
  Particles q;
  q.resize(which.size());
  for (std::size_t k = 0; k < which.size(); ++k) {
    const std::uint32_t o = which[k];
    q.position[k] = position[o];
    q.velocity[k] = velocity[o];
    q.direction[k] = direction[o];
    q.mass[k] = mass[o];
    q.is_root[k] = is_root[o];
    q.uv[k] = uv[o];
    q.arc_length[k] = arc_length[o];
    q.root_point[k] = root_point[o];
  }
  return q;
}

namespace {
bool finite3(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
}  // namespace

void Particles::check() const {
  const std::size_t n = position.size();
  if (velocity.size() != n || direction.size() != n || mass.size() != n || is_root.size() != n || uv.size() != n ||
      arc_length.size() != n || root_point.size() != n)
    throw std::invalid_argument("particle arrays have different lengths");
  if (n > 0xfffffff0u) throw std::invalid_argument("too many particles: " + std::to_string(n));
  for (std::size_t i = 0; i < n; ++i) {
    const std::string at = "particle " + std::to_string(i) + ": ";
    if (!finite3(position[i]) || !finite3(velocity[i]) || !finite3(root_point[i]))
      throw std::invalid_argument(at + "non-finite position, velocity or root point");
    if (!(mass[i] > 0.0f) || !std::isfinite(mass[i])) {
      char buf[48];
      std::snprintf(buf, sizeof buf, "%g", static_cast<double>(mass[i]));
      throw std::invalid_argument(at + "mass " + buf + " kg is not positive");
    }
    const float len = glm::length(direction[i]);
    if (!(std::abs(len - 1.0f) < 1e-3f)) throw std::invalid_argument(at + "hair direction is not a unit vector");
    // roots have s < 0; a particle held by a hair tie is a root further along
    if (!std::isfinite(arc_length[i]) || (arc_length[i] < 0.0f && is_root[i] == 0))
      throw std::invalid_argument(at + "root flag disagrees with arc length s = " + std::to_string(arc_length[i]) +
                                  " (particles with s < 0 are roots)");
  }
}

}  // namespace loosehair
