// OpenGL object names that free themselves: a program, buffer, vertex
// array, texture or framebuffer is deleted with the handle that owns it
// (in the context current then: the renderer's owner keeps its context
// current while the renderer lives). Move-only.
#pragma once

#include "loosehair/render/gl_functions.hpp"

#include <utility>

namespace loosehair::render {

template <class Kind>
class GlName {
 public:
  GlName() = default;
  explicit GlName(GLuint name) : name_(name) {}
  ~GlName() { reset(); }
  GlName(GlName&& other) noexcept : name_(std::exchange(other.name_, 0)) {}
  GlName& operator=(GlName&& other) noexcept {
    if (this != &other) {
      reset();
      name_ = std::exchange(other.name_, 0);
    }
    return *this;
  }
  GlName(const GlName&) = delete;
  GlName& operator=(const GlName&) = delete;

  /// A new object of this kind (glGen*).
  static GlName make() { return GlName(Kind::generate()); }
  GLuint get() const { return name_; }
  /// Deletes the object held, if any, and takes `name`.
  void reset(GLuint name = 0) {
    if (name_ != 0) Kind::destroy(name_);
    name_ = name;
  }

 private:
  GLuint name_ = 0;
};

namespace gl_kind {
struct Program {  // made by linking (gl_program.hpp): GlProgram(program(...))
  static void destroy(GLuint n) { glDeleteProgram(n); }
};
struct Buffer {
  static GLuint generate() {
    GLuint n = 0;
    glGenBuffers(1, &n);
    return n;
  }
  static void destroy(GLuint n) { glDeleteBuffers(1, &n); }
};
struct VertexArray {
  static GLuint generate() {
    GLuint n = 0;
    glGenVertexArrays(1, &n);
    return n;
  }
  static void destroy(GLuint n) { glDeleteVertexArrays(1, &n); }
};
struct Texture {
  static GLuint generate() {
    GLuint n = 0;
    glGenTextures(1, &n);
    return n;
  }
  static void destroy(GLuint n) { glDeleteTextures(1, &n); }
};
struct Framebuffer {
  static GLuint generate() {
    GLuint n = 0;
    glGenFramebuffers(1, &n);
    return n;
  }
  static void destroy(GLuint n) { glDeleteFramebuffers(1, &n); }
};
}  // namespace gl_kind

using GlProgram = GlName<gl_kind::Program>;
using GlBuffer = GlName<gl_kind::Buffer>;
using GlVertexArray = GlName<gl_kind::VertexArray>;
using GlTexture = GlName<gl_kind::Texture>;
using GlFramebuffer = GlName<gl_kind::Framebuffer>;

}  // namespace loosehair::render
