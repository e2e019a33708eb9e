// An OpenGL 3.3 core context without a display (method.md §7.4), drawing into
// a picture this object owns: OSMesa (software, llvmpipe; the default) or
// EGL (a GPU where the machine has one: the device platform, else Mesa's
// surfaceless platform), neither needing an X server. Making it loads the
// renderer's GL functions through the provider's get-proc-address.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace loosehair::app {

enum class GLProvider { OSMesa, EGL };
/// "osmesa" or "egl"; throws std::invalid_argument otherwise.
GLProvider parseGLProvider(const std::string& name);

class HeadlessGL {
 public:
  /// Creates the context and makes it current; throws std::runtime_error
  /// saying what is missing.
  HeadlessGL(int width, int height, GLProvider provider = GLProvider::OSMesa);
  ~HeadlessGL();
  HeadlessGL(const HeadlessGL&) = delete;
  HeadlessGL& operator=(const HeadlessGL&) = delete;

  int width() const { return width_; }
  int height() const { return height_; }
  /// The finished frame, RGBA8, top row first.
  std::vector<std::uint8_t> pixels() const;
  std::string renderer() const;

  struct Context;  // headless_osmesa.cpp, headless_egl.cpp

 private:
  std::unique_ptr<Context> context_;
  int width_, height_;
};

}  // namespace loosehair::app
