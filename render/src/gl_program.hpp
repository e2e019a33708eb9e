// Compiling and linking GLSL programs (errors as RenderError with the log).
#pragma once

#include <GL/glcorearb.h>

#include <string>

namespace loosehair::render {

GLuint compile(GLenum type, const std::string& src);
GLuint program(const std::string& vs, const std::string& fs);

}  // namespace loosehair::render
