// Framebuffers the renderer draws into before the picture reaches the one it
// was given: the opaque picture (colour and depth, at the supersampled size),
// the strands' transparency sums sharing its depth, and the resolve of
// supersampling into the caller's framebuffer.
#pragma once

#include "gl_handles.hpp"

namespace loosehair::render {

class OffscreenTarget {
 public:
  OffscreenTarget() = default;
  ~OffscreenTarget() = default;
  OffscreenTarget(const OffscreenTarget&) = delete;
  OffscreenTarget& operator=(const OffscreenTarget&) = delete;

  /// (Re)allocates for width x height; `transparency` adds the two sum
  /// targets of weighted blended transparency (RGBA16F and R16F).
  void resize(int width, int height, bool transparency);
  /// The opaque picture (colour + depth) as the draw target.
  void bindOpaque() const;
  /// The transparency sums (with the opaque depth, not written) as the target.
  void bindTransparency() const;
  int width() const { return width_; }
  int height() const { return height_; }
  GLuint color() const { return color_.get(); }
  GLuint accum() const { return accum_.get(); }
  GLuint reveal() const { return reveal_.get(); }

 private:
  void release();
  int width_ = 0, height_ = 0;
  bool transparency_ = false;
  GlFramebuffer opaque_fbo_, oit_fbo_;
  GlTexture color_, depth_, accum_, reveal_;
};

}  // namespace loosehair::render
