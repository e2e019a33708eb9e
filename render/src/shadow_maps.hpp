// The opacity shadow maps (method.md §7.2): 16 slices in 5 RGBA layers,
// neighbouring layers sharing a slice, starting per texel at the hair
// nearest the light (deep opacity maps: the nearest-hair target).
#pragma once

#include "gl_handles.hpp"

#include <glm/mat4x4.hpp>

namespace loosehair::render {

class ShadowMaps {
 public:
  ShadowMaps();  // needs the context current; restores its framebuffer binding

  /// The nearest-hair target, cleared to "nothing near", as the draw target
  /// (a MIN blend draws into it).
  void beginNearest() const;
  /// The slices, cleared, as the draw target (an additive blend).
  void beginSlices() const;
  /// Program p's lookups (it is in use): u_light_coords, u_kappa,
  /// u_shadows, the slices on unit 1 and the nearest depths on
  /// StrandPass::kNearestUnit.
  void bindLookups(GLuint p, const glm::mat4& light_coords, float kappa, bool shadows) const;
  GLuint slices() const { return slice_tex_.get(); }
  GLuint nearest() const { return nearest_tex_.get(); }

 private:
  GlFramebuffer shadow_fbo_, nearest_fbo_;
  GlTexture slice_tex_;    // 2-D array, 5 layers of RGBA8: the 16 slices
  GlTexture nearest_tex_;  // R32F: the depth (slices) of the hair nearest the light
};

}  // namespace loosehair::render
