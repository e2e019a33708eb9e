// The head a scene or style grows hair on, built: the head and torso as
// collision bodies (method.md §5) and the scalp with its harmonic map to the unit
// square (method.md §6.1), with the queries styling needs (a point and normal for
// any (u, v), the (u, v) of the scalp point nearest to a point, and the
// scalp's triangles for picking and for regions made of triangles).
#pragma once

#include "loosehair/body.hpp"
#include "loosehair/mesh.hpp"
#include "loosehair/scene.hpp"

#include <glm/vec2.hpp>

#include <memory>
#include <string>
#include <vector>

namespace loosehair {

class ScalpSurface;  // sim/src/init/scalp_surface.hpp

/// The scalp as triangles: 3-D positions in the head frame, the (u, v) of
/// each vertex, counter-clockwise triangles seen from outside. For a mesh
/// head these are the trimmed mesh's own triangles; for a sphere cap a grid
/// over the (u, v) square mapped onto the cap.
struct ScalpTriangles {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec2> uvs;
  std::vector<glm::u32vec3> triangles;
  std::vector<double> areas;  // m^2, per triangle
};

class NearestTriangle;

class HeadModel {
 public:
  /// Loads and checks the meshes, bakes their distance fields and builds the
  /// scalp. Throws SceneError naming `source` and the field. `report`
  /// receives the mesh figures, timings and warnings.
  static HeadModel build(const HeadDesc& desc, const std::string& source, const MeshLimits& limits = {},
                         BuildReport* report = nullptr);
  HeadModel(HeadModel&&) noexcept;
  HeadModel& operator=(HeadModel&&) noexcept;
  ~HeadModel();

  const HeadDesc& desc() const { return desc_; }
  std::shared_ptr<const Body> head() const { return head_; }
  std::shared_ptr<const Body> torso() const { return torso_; }  // null without one
  /// The head mesh (a sphere head: a tessellated sphere), head frame.
  const TriangleMesh& headMesh() const { return head_mesh_; }

  glm::vec3 scalpPoint(glm::vec2 uv) const;
  glm::vec3 scalpNormal(glm::vec2 uv) const;
  /// A unit tangent of the scalp at uv along increasing u (orthogonal to the
  /// normal): with the normal it makes the local frame of a root.
  glm::vec3 scalpTangentU(glm::vec2 uv) const;
  /// The (u, v) of the scalp point nearest to p; `distance` receives |p - point|.
  glm::vec2 nearestScalpUv(glm::vec3 p, float* distance = nullptr) const;
  /// The scalp triangle holding (u, v) (the nearest one outside the square).
  std::uint32_t scalpTriangleAt(glm::vec2 uv) const;
  const ScalpTriangles& scalpTriangles() const { return tris_; }
  /// Every scalp triangle whose (u, v) box overlaps the box [lo, hi] (and
  /// perhaps a few more nearby), sorted, without repeats.
  std::vector<std::uint32_t> scalpTrianglesNear(glm::vec2 lo, glm::vec2 hi) const;
  double scalpArea() const;
  /// The head frame's left/right plane is x = mirrorPlaneX() (the middle of
  /// the head mesh's extent in x).
  float mirrorPlaneX() const { return mirror_x_; }
  /// Signed distance to the head (m), negative inside.
  float headDistance(glm::vec3 p) const;

  const ScalpSurface& scalp() const { return *scalp_; }

 private:
  HeadModel();
  void buildMeshHead(const HeadDesc& desc, const std::string& source, const MeshLimits& limits, BuildReport& rep);
  void buildScalpTables();
  HeadDesc desc_;
  std::shared_ptr<const Body> head_, torso_;
  std::unique_ptr<ScalpSurface> scalp_;
  TriangleMesh head_mesh_;
  ScalpTriangles tris_;
  std::unique_ptr<NearestTriangle> nearest_;                // the scalp triangles, for nearestScalpUv
  std::vector<std::uint32_t> bucket_start_, bucket_items_;  // uv buckets of triangles
  int buckets_ = 1;
  float mirror_x_ = 0.0f;
};

}  // namespace loosehair
