// The hair as billboards (method.md §7.1): one textured quad a particle,
// sorted back to front, drawn into the opacity maps from the light and
// shaded (Kajiya-Kay, the maps' shadows) from the camera.
#pragma once

#include "gl_handles.hpp"
#include "loosehair/render/frame.hpp"
#include "loosehair/render/renderer.hpp"

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace loosehair::render {

class ShadowMaps;

/// The quads' size and opacity (world metres: the settings' factors times
/// the particle spacing).
struct BillboardLook {
  float width = 0, length = 0, max_boost = 0, opacity = 0;
};

class BillboardPass {
 public:
  BillboardPass();
  /// The particles of `in` sorted back to front for `view` and uploaded as
  /// quads, each with its value (the debug views' colour source; may be
  /// shorter than the particles: 0). Times the sort and the upload.
  void upload(const FrameInput& in, const glm::mat4& view, const std::vector<float>& values, FrameTimes& times);
  /// Into the opacity maps (the nearest-hair target when `nearest_pass`):
  /// the light's view-projection and slice coordinates.
  void drawOpacity(const BillboardLook& look, const glm::mat4& light_view_proj, const glm::mat4& slice_coords,
                   const glm::vec3& light, float pixel_scale, bool nearest_pass, GLuint nearest_tex) const;
  /// Shaded from the camera, blended back to front over the bodies.
  struct Shading {
    glm::mat4 view_proj{1.0f};
    glm::vec3 eye{0.0f}, light{0.0f}, color{0.0f}, spec{0.0f};
    float pixel_scale = 0;
  };
  void drawShaded(const BillboardLook& look, const Shading& sh, const ShadowMaps& shadows,
                  const glm::mat4& light_coords, float kappa, bool shadows_on) const;

 private:
  void setLook(GLuint p, const BillboardLook& look) const;
  void draw(GLuint p) const;
  GlProgram hair_prog_, opacity_prog_;
  GlTexture hair_tex_;
  // 4 vertices each (not instances: llvmpipe runs the vertex stage once per
  // instance, which cost more than the fragments at 20k particles), drawn
  // as 2 triangles each from a shared index buffer
  GlVertexArray quad_vao_;
  GlBuffer quad_vbo_, quad_ibo_;
  std::size_t quad_capacity_ = 0;  // billboards the index buffer holds
  std::size_t count_ = 0;          // billboards uploaded
  std::vector<float> depth_, quads_;
  std::vector<std::uint32_t> quad_indices_, order_, scratch_;
};

}  // namespace loosehair::render
