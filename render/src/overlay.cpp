
#include "loosehair/render/gl_functions.hpp"

#include "loosehair/render/overlay.hpp"
#include "loosehair/render/shaders.hpp"
#include "gl_handles.hpp"
#include "gl_program.hpp"

#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>

namespace loosehair::render {

void OverlayLines::line(glm::vec3 a, glm::vec3 b, glm::vec4 color) {
  points.push_back(a);
  points.push_back(b);
  colors.push_back(color);
  colors.push_back(color);
}

void OverlayLines::polyline(const std::vector<glm::vec3>& p, glm::vec4 color) {
  for (std::size_t k = 1; k < p.size(); ++k) line(p[k - 1], p[k], color);
}

void OverlayLines::arrow(glm::vec3 from, glm::vec3 to, glm::vec4 color) {
  line(from, to, color);
  const glm::vec3 d = to - from;
  const float len = glm::length(d);
  if (!(len > 0)) return;
  const glm::vec3 t = d / len;
  const glm::vec3 helper = std::abs(t.y) < 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
  const glm::vec3 u = glm::normalize(glm::cross(t, helper)), v = glm::cross(t, u);
  const float head = 0.25f * len, spread = 0.4f * head;
  for (const glm::vec3 side : {u, -u, v, -v}) line(to, to - head * t + spread * side, color);
}

void OverlayLines::box(glm::vec3 lo, glm::vec3 hi, glm::vec4 color) {
  for (int axis = 0; axis < 3; ++axis) {
    const int a = (axis + 1) % 3, b = (axis + 2) % 3;
    for (int k = 0; k < 4; ++k) {
      glm::vec3 p = lo, q = lo;
      p[a] = q[a] = (k & 1) ? hi[a] : lo[a];
      p[b] = q[b] = (k & 2) ? hi[b] : lo[b];
      q[axis] = hi[axis];
      line(p, q, color);
    }
  }
}

void OverlayLines::cross(glm::vec3 c, float r, glm::vec4 color) {
  for (int axis = 0; axis < 3; ++axis) {
    glm::vec3 d(0.0f);
    d[axis] = r;
    line(c - d, c + d, color);
  }
}

struct OverlayRenderer::Impl {
  GlProgram prog;
  GlVertexArray vao;
  GlBuffer vbo_pos, vbo_color;
  GLint view_proj = -1;
};

OverlayRenderer::OverlayRenderer() : impl_(std::make_unique<Impl>()) {
  Impl& r = *impl_;
  r.prog.reset(program(shaders::overlay_vert, shaders::overlay_frag));
  r.view_proj = glGetUniformLocation(r.prog.get(), "u_view_proj");
  r.vao = GlVertexArray::make();
  r.vbo_pos = GlBuffer::make();
  r.vbo_color = GlBuffer::make();
  glBindVertexArray(r.vao.get());
  glBindBuffer(GL_ARRAY_BUFFER, r.vbo_pos.get());
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
  glBindBuffer(GL_ARRAY_BUFFER, r.vbo_color.get());
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, 0, nullptr);
  glBindVertexArray(0);
}

OverlayRenderer::~OverlayRenderer() = default;

void OverlayRenderer::draw(const OverlayLines& hidden, const OverlayLines& on_top, const Camera& camera, int width,
                           int height) {
  if (hidden.empty() && on_top.empty()) return;
  Impl& r = *impl_;
  const float aspect = static_cast<float>(width) / static_cast<float>(height > 0 ? height : 1);
  const glm::mat4 vp = camera.projection(aspect) * camera.view();
  glViewport(0, 0, width, height);
  glUseProgram(r.prog.get());
  glUniformMatrix4fv(r.view_proj, 1, GL_FALSE, glm::value_ptr(vp));
  glBindVertexArray(r.vao.get());
  glEnable(GL_BLEND);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  glDepthMask(GL_FALSE);
  for (const OverlayLines* lines : {&hidden, &on_top}) {
    if (lines->empty()) continue;
    if (lines == &hidden)
      glEnable(GL_DEPTH_TEST);
    else
      glDisable(GL_DEPTH_TEST);
    glDepthFunc(GL_LEQUAL);
    glBindBuffer(GL_ARRAY_BUFFER, r.vbo_pos.get());
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(lines->points.size() * sizeof(glm::vec3)),
                 lines->points.data(), GL_STREAM_DRAW);
    glBindBuffer(GL_ARRAY_BUFFER, r.vbo_color.get());
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(lines->colors.size() * sizeof(glm::vec4)),
                 lines->colors.data(), GL_STREAM_DRAW);
    glDrawArrays(GL_LINES, 0, static_cast<GLsizei>(lines->points.size()));
  }
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);
  glBindVertexArray(0);
  glUseProgram(0);
}

}  // namespace loosehair::render
