
#include "gl_program.hpp"

#include <glm/gtc/type_ptr.hpp>

#include "loosehair/render/renderer.hpp"

#include <initializer_list>

namespace loosehair::render {

GLuint compile(GLenum type, const std::string& src) {
  const GLuint s = glCreateShader(type);
  const char* p = src.c_str();
  glShaderSource(s, 1, &p, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[2048];
    glGetShaderInfoLog(s, sizeof log, nullptr, log);
    glDeleteShader(s);
    throw RenderError(std::string("shader does not compile: ") + log);
  }
  return s;
}

namespace {
// links `p` from the shaders attached to it (deleted after), or throws
GLuint link(GLuint p, std::initializer_list<GLuint> shaders) {
  for (GLuint s : shaders) glAttachShader(p, s);
  glLinkProgram(p);
  for (GLuint s : shaders) glDeleteShader(s);
  GLint ok = 0;
  glGetProgramiv(p, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[2048];
    glGetProgramInfoLog(p, sizeof log, nullptr, log);
    glDeleteProgram(p);
    throw RenderError(std::string("shader program does not link: ") + log);
  }
  return p;
}
}  // namespace

GLuint program(const std::string& vs, const std::string& fs) {
  const GLuint v = compile(GL_VERTEX_SHADER, vs), f = compile(GL_FRAGMENT_SHADER, fs);
  return link(glCreateProgram(), {v, f});
}

GLuint computeProgram(const std::string& cs) { return link(glCreateProgram(), {compile(GL_COMPUTE_SHADER, cs)}); }

GLint loc(GLuint p, const char* name) { return glGetUniformLocation(p, name); }
void setMat(GLuint p, const char* n, const glm::mat4& m) {
  glUniformMatrix4fv(loc(p, n), 1, GL_FALSE, glm::value_ptr(m));
}
void setVec(GLuint p, const char* n, const glm::vec3& v) { glUniform3fv(loc(p, n), 1, glm::value_ptr(v)); }
void setF(GLuint p, const char* n, float v) { glUniform1f(loc(p, n), v); }
void setI(GLuint p, const char* n, int v) { glUniform1i(loc(p, n), v); }

void setHairShading(GLuint p, const glm::vec3& light, const glm::vec3& color, const glm::vec3& spec_color,
                    float ambient) {
  setVec(p, "u_light", light);
  setVec(p, "u_color", color);
  setVec(p, "u_spec_color", spec_color);
  setF(p, "u_kd", 1.0f);
  setF(p, "u_ks", 0.6f);
  setF(p, "u_shine", 40.0f);
  setF(p, "u_reflect", 1.0f);
  setF(p, "u_transmit", 0.45f);
  setF(p, "u_ambient", ambient);
}

}  // namespace loosehair::render
