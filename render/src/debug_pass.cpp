// The debug views (debug_pass.hpp).
#include "debug_pass.hpp"

#include "loosehair/render/shaders.hpp"
#include "gl_program.hpp"

namespace loosehair::render {

DebugPass::DebugPass() : prog_(program(shaders::debug_vert, shaders::debug_frag)) {
  vao_ = GlVertexArray::make();
  vbo_ = GlBuffer::make();
  glBindVertexArray(vao_.get());
  glBindBuffer(GL_ARRAY_BUFFER, vbo_.get());
  glEnableVertexAttribArray(0);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 16, nullptr);
  glVertexAttribPointer(1, 1, GL_FLOAT, GL_FALSE, 16, reinterpret_cast<void*>(12));
  glBindVertexArray(0);
}

void DebugPass::draw(const FrameInput& in, const RenderSettings& settings, const glm::mat4& view_proj) {
  const std::size_t n = in.position.size();
  const GLuint p = prog_.get();
  glUseProgram(p);
  setMat(p, "u_view_proj", view_proj);
  lines_.clear();
  GLenum mode = GL_POINTS;
  if (settings.debug == DebugView::Density || settings.debug == DebugView::Speed) {
    const auto& values = settings.debug == DebugView::Density ? in.density : in.speed;
    for (std::size_t i = 0; i < n; ++i) {
      const float v = i < values.size() ? values[i] : 0.0f;
      lines_.insert(lines_.end(), {in.position[i].x, in.position[i].y, in.position[i].z, v});
    }
    const DebugLegend legend = debugLegend(in, settings);
    glUniform2f(loc(p, "u_range"), legend.low, legend.high);
    glUniform3fv(loc(p, "u_ramp"), 4, &kDebugRamp[0][0]);
    setI(p, "u_use_flat", 0);
    setF(p, "u_point_size", 3.0f);
    glEnable(GL_PROGRAM_POINT_SIZE);
  } else if (settings.debug == DebugView::Connections) {
    for (std::size_t k = 0; k + 1 < in.connections.size(); k += 2) {
      const glm::vec3 a = in.position[in.connections[k]], b = in.position[in.connections[k + 1]];
      lines_.insert(lines_.end(), {a.x, a.y, a.z, 0.0f, b.x, b.y, b.z, 0.0f});
    }
    setI(p, "u_use_flat", 1);
    setVec(p, "u_flat", glm::vec3(0.15f, 0.35f, 0.8f));
    mode = GL_LINES;
  } else {
    for (std::size_t i = 0; i < n; ++i) {
      const glm::vec3 a = in.position[i], b = a + 1.5f * in.spacing * in.direction[i];
      lines_.insert(lines_.end(), {a.x, a.y, a.z, 0.0f, b.x, b.y, b.z, 0.0f});
    }
    setI(p, "u_use_flat", 1);
    setVec(p, "u_flat", glm::vec3(0.7f, 0.2f, 0.1f));
    mode = GL_LINES;
  }
  glBindVertexArray(vao_.get());
  glBindBuffer(GL_ARRAY_BUFFER, vbo_.get());
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(lines_.size() * sizeof(float)), lines_.data(), GL_STREAM_DRAW);
  glDrawArrays(mode, 0, static_cast<GLsizei>(lines_.size() / 4));
}

}  // namespace loosehair::render
