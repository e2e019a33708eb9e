// Exact distances from points to a closed triangle mesh (method.md §5 body
// collisions), for MeshBody's contacts and for the voxels of the grid bake.
#pragma once

#include "loosehair/mesh.hpp"

#include <glm/vec3.hpp>

#include <cstdint>
#include <memory>
#include <vector>

namespace loosehair {

class ExactDistance {
 public:
  /// `mesh` closed and consistently oriented (as checkMesh leaves it).
  explicit ExactDistance(const TriangleMesh& mesh);
  ~ExactDistance();
  ExactDistance(const ExactDistance&) = delete;
  ExactDistance& operator=(const ExactDistance&) = delete;

  struct Nearest {
    float signed_distance;   // m, negative inside (the union of the parts)
    glm::vec3 normal;        // unit, outward: away from the point inside, towards it outside
    std::uint32_t triangle;  // the nearest triangle
  };
  /// The nearest point to p of each part (connected piece) within `radius`
  /// (infinite: anywhere), signed by its pseudo-normal; of these the one
  /// with the lowest signed distance, so the parts act as their union
  /// (overlapping closed parts such as eyeballs set into a head). `seeds`
  /// (count of them; out-of-range ids are ignored) are tried first and only
  /// make the search faster. Ties go to the lower triangle id, so the
  /// answer does not depend on the seeds. False if no part is in reach.
  bool nearest(const glm::vec3& p, float radius, const std::int32_t* seeds, int count, Nearest& out) const;
  /// nearest() anywhere: the signed distance, `normal` (optional) and the
  /// nearest triangle (optional).
  float signedDistance(const glm::vec3& p, const std::int32_t* seeds, int count, glm::vec3* normal = nullptr,
                       std::uint32_t* triangle = nullptr) const;

 private:
  struct Tree;
  std::vector<std::unique_ptr<Tree>> trees_;  // one a part
  std::vector<std::uint32_t> part_, local_;   // per triangle: its part, its id there
};

}  // namespace loosehair
