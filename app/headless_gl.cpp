#include "headless_gl.hpp"

#include "headless_gl_context.hpp"

#include <stdexcept>

namespace loosehair::app {

GLProvider parseGLProvider(const std::string& name) {
  if (name == "osmesa") return GLProvider::OSMesa;
  if (name == "egl") return GLProvider::EGL;
  throw std::invalid_argument("unknown OpenGL provider \"" + name + "\" (use osmesa or egl)");
}

HeadlessGL::HeadlessGL(int width, int height, GLProvider provider) : width_(width), height_(height) {
  if (width < 1 || height < 1 || width > 8192 || height > 8192)
    throw std::runtime_error("image size " + std::to_string(width) + "x" + std::to_string(height) +
                             " is not in 1..8192");
  context_ = provider == GLProvider::EGL ? makeEGLContext(width, height) : makeOSMesaContext(width, height);
}

HeadlessGL::~HeadlessGL() = default;

std::vector<std::uint8_t> HeadlessGL::pixels() const { return context_->pixels(width_, height_); }

std::string HeadlessGL::renderer() const { return context_->renderer(); }

}  // namespace loosehair::app
