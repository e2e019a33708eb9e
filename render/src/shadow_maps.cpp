// The opacity shadow maps' targets and lookups (method.md §7.2).
#include "shadow_maps.hpp"

#include "loosehair/render/renderer.hpp"
#include "gl_program.hpp"
#include "render_passes.hpp"
#include "strand_pass.hpp"

#include <string>

namespace loosehair::render {
namespace {

void clampedTexture(GLenum target, GLint filter) {
  glTexParameteri(target, GL_TEXTURE_MIN_FILTER, filter);
  glTexParameteri(target, GL_TEXTURE_MAG_FILTER, filter);
  glTexParameteri(target, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(target, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

}  // namespace

ShadowMaps::ShadowMaps() {
  GLint previous_fbo = 0;  // restored below: the caller's picture may be a framebuffer object
  glGetIntegerv(GL_FRAMEBUFFER_BINDING, &previous_fbo);
  shadow_fbo_ = GlFramebuffer::make();
  glBindFramebuffer(GL_FRAMEBUFFER, shadow_fbo_.get());
  slice_tex_ = GlTexture::make();
  glBindTexture(GL_TEXTURE_2D_ARRAY, slice_tex_.get());
  glTexImage3D(GL_TEXTURE_2D_ARRAY, 0, GL_RGBA8, kShadowSize, kShadowSize, kSliceLayers, 0, GL_RGBA, GL_UNSIGNED_BYTE,
               nullptr);
  clampedTexture(GL_TEXTURE_2D_ARRAY, GL_LINEAR);
  GLint max_buffers = 0;
  glGetIntegerv(GL_MAX_DRAW_BUFFERS, &max_buffers);
  if (max_buffers < kSliceLayers)
    throw RenderError("the OpenGL implementation draws into " + std::to_string(max_buffers) +
                      " targets at once; the opacity maps need " + std::to_string(kSliceLayers));
  GLenum bufs[kSliceLayers];
  for (int k = 0; k < kSliceLayers; ++k) {
    bufs[k] = GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(k);
    glFramebufferTextureLayer(GL_FRAMEBUFFER, bufs[k], slice_tex_.get(), 0, k);
  }
  glDrawBuffers(kSliceLayers, bufs);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw RenderError("the opacity-map framebuffer is incomplete");
  nearest_fbo_ = GlFramebuffer::make();
  glBindFramebuffer(GL_FRAMEBUFFER, nearest_fbo_.get());
  nearest_tex_ = GlTexture::make();
  glBindTexture(GL_TEXTURE_2D, nearest_tex_.get());
  glTexImage2D(GL_TEXTURE_2D, 0, GL_R32F, kShadowSize, kShadowSize, 0, GL_RED, GL_FLOAT, nullptr);
  clampedTexture(GL_TEXTURE_2D, GL_NEAREST);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, nearest_tex_.get(), 0);
  const GLenum one = GL_COLOR_ATTACHMENT0;
  glDrawBuffers(1, &one);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw RenderError("the nearest-hair framebuffer is incomplete");
  glBindFramebuffer(GL_FRAMEBUFFER, static_cast<GLuint>(previous_fbo));
}

void ShadowMaps::beginNearest() const {
  glBindFramebuffer(GL_FRAMEBUFFER, nearest_fbo_.get());
  glViewport(0, 0, kShadowSize, kShadowSize);
  glClearColor(1e6f, 1e6f, 1e6f, 1e6f);  // no hair: nothing nearer than far behind everything
  glClear(GL_COLOR_BUFFER_BIT);
}

void ShadowMaps::beginSlices() const {
  glBindFramebuffer(GL_FRAMEBUFFER, shadow_fbo_.get());
  glClearColor(0, 0, 0, 0);
  glClear(GL_COLOR_BUFFER_BIT);
}

void ShadowMaps::bindLookups(GLuint p, const glm::mat4& light_coords, float kappa, bool shadows) const {
  setMat(p, "u_light_coords", light_coords);
  setF(p, "u_kappa", kappa);
  setI(p, "u_shadows", shadows ? 1 : 0);
  glActiveTexture(GL_TEXTURE1);
  glBindTexture(GL_TEXTURE_2D_ARRAY, slice_tex_.get());
  setI(p, "u_slices", 1);
  glActiveTexture(GL_TEXTURE0 + StrandPass::kNearestUnit);
  glBindTexture(GL_TEXTURE_2D, nearest_tex_.get());
  setI(p, "u_nearest", StrandPass::kNearestUnit);
  glActiveTexture(GL_TEXTURE0);
}

}  // namespace loosehair::render
