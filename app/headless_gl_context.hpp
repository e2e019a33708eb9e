// The providers behind HeadlessGL (headless_osmesa.cpp, headless_egl.cpp).
#pragma once

#include "headless_gl.hpp"

namespace loosehair::app {

struct HeadlessGL::Context {
  virtual ~Context() = default;
  /// The frame, RGBA8, top row first.
  virtual std::vector<std::uint8_t> pixels(int width, int height) const = 0;
  virtual std::string renderer() const = 0;
};

std::unique_ptr<HeadlessGL::Context> makeOSMesaContext(int width, int height);
std::unique_ptr<HeadlessGL::Context> makeEGLContext(int width, int height);

}  // namespace loosehair::app
