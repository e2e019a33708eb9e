// Initial strand shape by a cantilever beam bending under gravity (Anjyo et
// al. 1992; method.md §6.1): the strand leaves the scalp along its root direction
// and each piece turns towards gravity by the moment of the hair below it,
// kappa(s) = (L - s)^2 sin(psi) / (2 S), S = EI / (weight per length).
// Pieces that would enter the body are pushed back out of it, to a clearance
// that grows along the strand (clearance + layering * s): a strand lying on
// the head lies on top of the hair rooted below it, so the hair keeps a
// volume instead of collapsing into one sheet on the scalp.
#pragma once

#include "loosehair/body.hpp"

#include <glm/vec3.hpp>

#include <limits>
#include <vector>

namespace loosehair {

class CantileverStrand {
 public:
  /// `stiffness` S in m^3; `body` may be null; the strand keeps at least
  /// clearance + layering * s outside the body at arc length s (m).
  /// A piece depends only on the pieces before it, so with `needed` < length
  /// only the pieces that position(s) and tangent(s) read for s <= needed
  /// are grown (a few more for rounding): their answers there are the same
  /// bits as the whole strand's, and points() is shorter.
  CantileverStrand(glm::vec3 root, glm::vec3 root_direction, glm::vec3 gravity_direction, float length, float stiffness,
                   const Body* body, float clearance, float layering, int segments,
                   float needed = std::numeric_limits<float>::infinity());

  /// Point and unit tangent at arc length s in [0, length] (clamped).
  glm::vec3 position(float s) const;
  glm::vec3 tangent(float s) const;
  float length() const { return length_; }
  const std::vector<glm::vec3>& points() const { return points_; }

 private:
  float length_, ds_;
  std::vector<glm::vec3> points_;
};

}  // namespace loosehair
