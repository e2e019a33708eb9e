// The bodies (head, torso) in the camera pass: lit, shadowed by the hair's
// opacity maps, writing the depth the hair is tested against.
#pragma once

#include "gl_handles.hpp"
#include "loosehair/mesh.hpp"

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

namespace loosehair::render {

class ShadowMaps;

class BodyPass {
 public:
  BodyPass();
  /// The meshes drawn (null: none); uploaded now.
  void setBodies(const TriangleMesh* head, const TriangleMesh* torso);
  /// Draws into the bound target (depth test on, no blending).
  void draw(const glm::mat4& view_proj, const glm::vec3& eye, const glm::vec3& light, const glm::mat4& head_pose,
            const ShadowMaps& shadows, const glm::mat4& light_coords, float kappa, bool shadows_on) const;

 private:
  struct Mesh {
    GlVertexArray vao;
    GlBuffer vbo, ibo;
    GLsizei count = 0;
  };
  static void upload(Mesh& b, const TriangleMesh* mesh);
  GlProgram prog_;
  Mesh head_, torso_;
};

}  // namespace loosehair::render
