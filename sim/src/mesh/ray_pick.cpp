#include "loosehair/ray_pick.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace loosehair {

std::optional<RayHit> intersectRay(const TriangleMesh& mesh, glm::vec3 origin, glm::vec3 dir) {
  const float len = glm::length(dir);
  if (!(len > 0) || !std::isfinite(len)) return std::nullopt;
  const glm::vec3 d = dir / len;
  std::optional<RayHit> best;
  // Moeller-Trumbore, both faces
  for (std::size_t t = 0; t < mesh.size(); ++t) {
    const glm::vec3 a = mesh.corner(t, 0), e1 = mesh.corner(t, 1) - a, e2 = mesh.corner(t, 2) - a;
    const glm::vec3 p = glm::cross(d, e2);
    const float det = glm::dot(e1, p);
    if (std::abs(det) < 1e-12f) continue;
    const float inv = 1.0f / det;
    const glm::vec3 s = origin - a;
    const float u = glm::dot(s, p) * inv;
    if (u < 0.0f || u > 1.0f) continue;
    const glm::vec3 q = glm::cross(s, e1);
    const float v = glm::dot(d, q) * inv;
    if (v < 0.0f || u + v > 1.0f) continue;
    const float dist = glm::dot(e2, q) * inv;
    if (dist <= 0.0f || (best && dist >= best->distance)) continue;
    best = RayHit{dist, static_cast<std::uint32_t>(t), origin + dist * d};
  }
  return best;
}

std::vector<std::uint32_t> scalpTrianglesWithin(const HeadModel& head, glm::vec3 point, float radius) {
  const ScalpTriangles& s = head.scalpTriangles();
  std::vector<std::uint32_t> out;
  const float r2 = radius * radius;
  for (std::size_t t = 0; t < s.triangles.size(); ++t) {
    const glm::vec3 a = s.positions[s.triangles[t][0]], b = s.positions[s.triangles[t][1]],
                    c = s.positions[s.triangles[t][2]];
    const glm::vec3 centre = (a + b + c) / 3.0f;
    bool in = false;
    for (const glm::vec3& q : {centre, a, b, c}) {
      const glm::vec3 d = q - point;
      in = in || glm::dot(d, d) <= r2;
    }
    if (in) out.push_back(static_cast<std::uint32_t>(t));
  }
  return out;
}

float distanceToRay(glm::vec3 p, glm::vec3 origin, glm::vec3 dir) {
  const float len2 = glm::dot(dir, dir);
  if (!(len2 > 0)) return glm::length(p - origin);
  const float t = std::max(0.0f, glm::dot(p - origin, dir) / len2);
  return glm::length(p - (origin + t * dir));
}

}  // namespace loosehair
