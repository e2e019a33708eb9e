#include "style/hair_tie.hpp"

#include <glm/geometric.hpp>

#include <cmath>

namespace loosehair {

std::optional<TieCrossing> crossTie(const std::vector<glm::vec3>& p, const HairTie& tie) {
  float s = 0;
  for (std::size_t i = 0; i + 1 < p.size(); ++i) {
    const float seg = glm::length(p[i + 1] - p[i]);
    const float a = glm::dot(p[i] - tie.center, tie.axis), b = glm::dot(p[i + 1] - tie.center, tie.axis);
    if ((a <= 0.0f) != (b <= 0.0f)) {
      const float t = a / (a - b);
      const glm::vec3 q = p[i] + t * (p[i + 1] - p[i]);
      const glm::vec3 r = q - tie.center;
      const float d = glm::length(r - glm::dot(r, tie.axis) * tie.axis);
      if (d <= tie.radius) return TieCrossing{s + t * seg, q, d};
    }
    s += seg;
  }
  return std::nullopt;
}

bool tieHoldsAKeyStrand(const Style& style, const HairTie& tie) {
  for (const Wisp& w : style.wisps)
    if (crossTie(sampleKeyStrand(w.key_strand, 16), tie)) return true;
  return false;
}

bool insideTie(const HairTie& tie, glm::vec3 p) {
  const glm::vec3 r = p - tie.center;
  const float along = glm::dot(r, tie.axis);
  return std::abs(along) <= 0.5f * tie.width && glm::length(r - along * tie.axis) <= tie.radius;
}

}  // namespace loosehair
