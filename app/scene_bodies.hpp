// The head and torso of a scene as meshes for drawing.
#pragma once

#include "loosehair/mesh.hpp"
#include "loosehair/scene.hpp"

#include <optional>

namespace loosehair::app {

struct DrawableBodies {
  TriangleMesh head;                  // head frame
  std::optional<TriangleMesh> torso;  // world frame, if the scene has one
};

/// The scene's head (its mesh, or a sphere) and torso, decimated for
/// drawing: llvmpipe shades vertices on one thread, and a picture needs far
/// fewer triangles than collision (the solver keeps the full meshes).
/// Throws what loadMesh throws.
DrawableBodies drawableBodies(const SceneDesc& scene);

}  // namespace loosehair::app
