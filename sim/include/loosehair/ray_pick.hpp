// Picking by rays (the viewer's styling brush and selection): where a ray
// from the eye first meets a triangle mesh, and the scalp triangles around
// a point. Head frame throughout.
#pragma once

#include "loosehair/head_model.hpp"
#include "loosehair/mesh.hpp"

#include <glm/vec3.hpp>

#include <cstdint>
#include <optional>
#include <vector>

namespace loosehair {

struct RayHit {
  float distance = 0;          // along the (unit) ray direction (m)
  std::uint32_t triangle = 0;  // index into the mesh's triangles
  glm::vec3 point{0.0f};
};

/// The nearest hit of the ray origin + t dir (t > 0, dir need not be unit)
/// with a triangle of `mesh`, from either side; nothing if it misses.
std::optional<RayHit> intersectRay(const TriangleMesh& mesh, glm::vec3 origin, glm::vec3 dir);

/// The scalp triangles (indices into head.scalpTriangles()) with a corner or
/// their centre within `radius` of `point`, sorted.
std::vector<std::uint32_t> scalpTrianglesWithin(const HeadModel& head, glm::vec3 point, float radius);

/// The distance from point p to the ray origin + t dir (t >= 0).
float distanceToRay(glm::vec3 p, glm::vec3 origin, glm::vec3 dir);

}  // namespace loosehair
