#include "scene_bodies.hpp"

#include <glm/vec3.hpp>

#include <cmath>

namespace loosehair::app {
namespace {

// A sphere head as a mesh for drawing.
TriangleMesh sphereMesh(glm::vec3 centre, float radius) {
  TriangleMesh m;
  const int rings = 48, segments = 96;
  for (int r = 0; r <= rings; ++r)
    for (int s = 0; s <= segments; ++s) {
      const float th = 3.14159265f * static_cast<float>(r) / rings, ph = 6.2831853f * static_cast<float>(s) / segments;
      m.vertices.push_back(centre +
                           radius * glm::vec3(std::sin(th) * std::cos(ph), std::cos(th), std::sin(th) * std::sin(ph)));
    }
  auto id = [&](int r, int s) { return static_cast<std::uint32_t>(r * (segments + 1) + s); };
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      m.triangles.emplace_back(id(r, s), id(r, s + 1), id(r + 1, s));
      m.triangles.emplace_back(id(r + 1, s), id(r, s + 1), id(r + 1, s + 1));
    }
  return m;
}

}  // namespace

DrawableBodies drawableBodies(const SceneDesc& scene) {
  DrawableBodies b;
  b.head = scene.head_kind == HeadKind::Mesh ? loadMesh(scene.head_mesh.path, scene.head_mesh.load)
                                             : sphereMesh(scene.head_center, scene.head_radius);
  b.head = decimate(b.head, 16000);
  if (scene.has_torso) b.torso = decimate(loadMesh(scene.torso_mesh.path, scene.torso_mesh.load), 8000);
  return b;
}

}  // namespace loosehair::app
