#include "headless_gl.hpp"

#include <GL/osmesa.h>

#include <cstring>
#include <stdexcept>

namespace loosehair::app {

HeadlessGL::HeadlessGL(int width, int height) : width_(width), height_(height) {
  if (width < 1 || height < 1 || width > 8192 || height > 8192)
    throw std::runtime_error("image size " + std::to_string(width) + "x" + std::to_string(height) +
                             " is not in 1..8192");
  const int attribs[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 24, OSMESA_STENCIL_BITS, 0,
                         OSMESA_PROFILE, OSMESA_CORE_PROFILE, OSMESA_CONTEXT_MAJOR_VERSION, 3,
                         OSMESA_CONTEXT_MINOR_VERSION, 3, 0};
  OSMesaContext ctx = OSMesaCreateContextAttribs(attribs, nullptr);
  if (!ctx) throw std::runtime_error("OSMesa cannot create an OpenGL 3.3 core context");
  context_ = ctx;
  buffer_.assign(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 4, 0);
  if (!OSMesaMakeCurrent(ctx, buffer_.data(), GL_UNSIGNED_BYTE, width, height)) {
    OSMesaDestroyContext(ctx);
    throw std::runtime_error("OSMesa cannot make its context current");
  }
}

HeadlessGL::~HeadlessGL() {
  if (context_) OSMesaDestroyContext(static_cast<OSMesaContext>(context_));
}

std::vector<std::uint8_t> HeadlessGL::pixels() const {
  glFinish();
  // OSMesa's rows go bottom to top.
  const std::size_t row = static_cast<std::size_t>(width_) * 4;
  std::vector<std::uint8_t> out(buffer_.size());
  for (int y = 0; y < height_; ++y)
    std::memcpy(&out[static_cast<std::size_t>(y) * row],
                &buffer_[static_cast<std::size_t>(height_ - 1 - y) * row], row);
  return out;
}

std::string HeadlessGL::renderer() const {
  const char* r = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  const char* v = reinterpret_cast<const char*>(glGetString(GL_VERSION));
  return std::string(r ? r : "?") + ", OpenGL " + (v ? v : "?");
}

}  // namespace loosehair::app
