// The bodies as a stage asks them: the nearest surface of any body (head,
// torso, obstacles) placed at one time, seen from the head frame. Solver
// answers with its placed bodies (bodies.cpp); a test answers with a plane.
#pragma once

#include <glm/vec3.hpp>

#include <cstddef>

namespace loosehair {

class BodyQuery {
 public:
  virtual ~BodyQuery() = default;
  /// phi (signed distance, negative inside), outward normal and surface
  /// velocity (head frame) of the nearest body at x[0..n). Exact where
  /// phi < limit; elsewhere phi >= limit and the rest unspecified. `rough`:
  /// answers may be the bodies' grid distances, within roughError().
  virtual void nearest(const glm::vec3* x, std::size_t n, float* phi, glm::vec3* normal, glm::vec3* surface_velocity,
                       float limit, bool rough) const = 0;
  /// The rough answers' worst error over these bodies (m); INFINITY: no bound.
  virtual float roughError() const = 0;
};

}  // namespace loosehair
