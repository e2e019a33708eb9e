// The debug views: particles as points coloured by density or speed, or
// the connections and directions as lines (render/shaders/debug.*).
#pragma once

#include "gl_handles.hpp"
#include "loosehair/render/frame.hpp"
#include "loosehair/render/renderer.hpp"

#include <glm/mat4x4.hpp>

#include <vector>

namespace loosehair::render {

// The density and speed views' ramp: blue to cyan over the lower half,
// yellow to red over the upper (debug.frag's u_ramp; debugRamp on the CPU).
inline constexpr float kDebugRamp[4][3] = {
    {0.1f, 0.2f, 0.9f}, {0.1f, 0.9f, 0.9f}, {0.95f, 0.9f, 0.1f}, {0.9f, 0.1f, 0.1f}};

class DebugPass {
 public:
  DebugPass();
  /// Draws `settings.debug`'s view of `in` into the bound target.
  void draw(const FrameInput& in, const RenderSettings& settings, const glm::mat4& view_proj);

 private:
  GlProgram prog_;
  GlVertexArray vao_;
  GlBuffer vbo_;
  std::vector<float> lines_;
};

}  // namespace loosehair::render
