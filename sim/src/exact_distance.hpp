// Exact distances from points to a closed triangle mesh (SPEC §5 body
// collisions), for MeshBody's contacts and for the voxels of the grid bake.
#pragma once

#include "loosehair/mesh.hpp"

#include <glm/vec3.hpp>

#include <cstdint>
#include <memory>

namespace loosehair {

class ExactDistance {
 public:
  /// `mesh` closed and consistently oriented (as checkMesh leaves it).
  explicit ExactDistance(const TriangleMesh& mesh);
  ~ExactDistance();
  ExactDistance(const ExactDistance&) = delete;
  ExactDistance& operator=(const ExactDistance&) = delete;

  struct Nearest {
    float distance;           // unsigned (m)
    glm::vec3 point;          // the nearest point of the mesh
    glm::vec3 pseudo_normal;  // of the nearest feature (not unit)
    glm::vec3 face_normal;    // of the nearest triangle (unit)
    std::uint32_t triangle;
  };
  /// The nearest point of the mesh to p, if one lies within `radius`
  /// (infinite: anywhere); `seeds` (count of them; out-of-range ids are
  /// ignored) are tried first and only make the search faster. Ties go to
  /// the lower triangle id, so the answer does not depend on the seeds.
  bool nearest(const glm::vec3& p, float radius, const std::int32_t* seeds, int count,
               Nearest& out) const;
  /// Signed by the pseudo-normal (negative inside); `normal` (optional) the
  /// unit outward direction away from the nearest point.
  float signedDistance(const glm::vec3& p, const std::int32_t* seeds, int count,
                       glm::vec3* normal = nullptr, std::uint32_t* triangle = nullptr) const;

 private:
  struct Tree;
  std::unique_ptr<Tree> tree_;
};

}  // namespace loosehair
