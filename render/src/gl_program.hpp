// Compiling and linking GLSL programs (errors as RenderError with the log).
#pragma once

#include "loosehair/render/gl_functions.hpp"

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <string>

namespace loosehair::render {

GLuint compile(GLenum type, const std::string& src);
GLuint program(const std::string& vs, const std::string& fs);
GLuint computeProgram(const std::string& cs);  // OpenGL 4.3

// Uniforms of the program in use, by name.
GLint loc(GLuint p, const char* name);
void setMat(GLuint p, const char* name, const glm::mat4& m);
void setVec(GLuint p, const char* name, const glm::vec3& v);
void setF(GLuint p, const char* name, float v);
void setI(GLuint p, const char* name, int v);

/// The hair shading terms of program p (render/shaders/kajiya_kay.glsl,
/// hair_shade.glsl, strand_shade.glsl): the light towards which it shades,
/// the colours, and the Kajiya-Kay weights every hair pass uses.
void setHairShading(GLuint p, const glm::vec3& light, const glm::vec3& color, const glm::vec3& spec_color,
                    float ambient);

}  // namespace loosehair::render
