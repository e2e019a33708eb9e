
#include "offscreen_target.hpp"

#include "loosehair/render/renderer.hpp"

#include <algorithm>

namespace loosehair::render {

namespace {
GlTexture texture(GLenum internal, GLenum format, GLenum type, int w, int h) {
  GlTexture t = GlTexture::make();
  glBindTexture(GL_TEXTURE_2D, t.get());
  glTexImage2D(GL_TEXTURE_2D, 0, static_cast<GLint>(internal), w, h, 0, format, type, nullptr);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  return t;
}
// A framebuffer that could not be made: which, how large, and what to do
// (the size limit OpenGL states, and that memory may run out below it).
void check(const char* what, int w, int h) {
  const GLenum error = glGetError();
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE && error == GL_NO_ERROR) return;
  GLint max_texture = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_texture);
  throw RenderError(std::string("the ") + what + " framebuffer of " + std::to_string(w) + "x" + std::to_string(h) +
                    " pixels (the size times the supersampling) could not be made" +
                    (error == GL_OUT_OF_MEMORY ? " (out of memory)" : "") + "; this OpenGL draws at most " +
                    std::to_string(max_texture) + " pixels a side and may run out of memory before: lower --size " +
                    "or --supersample (e.g. --size 4096x4096 --supersample 1)");
}
}  // namespace

void OffscreenTarget::release() {
  for (GlFramebuffer* f : {&opaque_fbo_, &oit_fbo_}) f->reset();
  for (GlTexture* t : {&color_, &depth_, &accum_, &reveal_}) t->reset();
  width_ = height_ = 0;
}

void OffscreenTarget::resize(int width, int height, bool transparency) {
  if (width == width_ && height == height_ && transparency == transparency_ && opaque_fbo_.get()) return;
  GLint max_size = 0, max_texture = 0;
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_size);
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_texture);
  max_size = std::min(max_size, max_texture);
  while (glGetError() != GL_NO_ERROR) {
  }  // earlier errors are not this one's
  if (width > max_size || height > max_size)
    throw RenderError("a " + std::to_string(width) + "x" + std::to_string(height) +
                      " picture is larger than this OpenGL draws (" + std::to_string(max_size) +
                      "); lower the size or the supersampling");
  // leaves the caller's framebuffer bound, whichever it is (an EGL
  // picture has no default framebuffer)
  GLint previous = 0;
  glGetIntegerv(GL_FRAMEBUFFER_BINDING, &previous);
  release();
  width_ = width;
  height_ = height;
  transparency_ = transparency;
  color_ = texture(GL_RGBA8, GL_RGBA, GL_UNSIGNED_BYTE, width, height);
  depth_ = texture(GL_DEPTH_COMPONENT24, GL_DEPTH_COMPONENT, GL_UNSIGNED_INT, width, height);
  opaque_fbo_ = GlFramebuffer::make();
  glBindFramebuffer(GL_FRAMEBUFFER, opaque_fbo_.get());
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, color_.get(), 0);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, depth_.get(), 0);
  check("picture", width, height);
  if (transparency) {
    accum_ = texture(GL_RGBA16F, GL_RGBA, GL_HALF_FLOAT, width, height);
    reveal_ = texture(GL_R16F, GL_RED, GL_HALF_FLOAT, width, height);
    oit_fbo_ = GlFramebuffer::make();
    glBindFramebuffer(GL_FRAMEBUFFER, oit_fbo_.get());
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, accum_.get(), 0);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, reveal_.get(), 0);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, depth_.get(), 0);
    const GLenum bufs[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glDrawBuffers(2, bufs);
    check("transparency", width, height);
  }
  glBindFramebuffer(GL_FRAMEBUFFER, static_cast<GLuint>(previous));
}

void OffscreenTarget::bindOpaque() const {
  glBindFramebuffer(GL_FRAMEBUFFER, opaque_fbo_.get());
  glViewport(0, 0, width_, height_);
}

void OffscreenTarget::bindTransparency() const {
  glBindFramebuffer(GL_FRAMEBUFFER, oit_fbo_.get());
  glViewport(0, 0, width_, height_);
}

}  // namespace loosehair::render
