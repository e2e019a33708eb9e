// Lines drawn over the picture (world coordinates): the viewer's styling
// previews (member strands, key strands, the three styling arrows), the
// wind and light arrows, neighbour-grid cells. Drawn into the current
// OpenGL 3.3 core context after Renderer::render, with the same camera.
#pragma once

#include "loosehair/render/renderer.hpp"

#include <glm/vec4.hpp>

#include <memory>
#include <vector>

namespace loosehair::render {

/// Line segments, two vertices each, with a colour per vertex.
struct OverlayLines {
  std::vector<glm::vec3> points;
  std::vector<glm::vec4> colors;
  void clear() {
    points.clear();
    colors.clear();
  }
  bool empty() const { return points.empty(); }
  void line(glm::vec3 a, glm::vec3 b, glm::vec4 color);
  /// Segments between consecutive points.
  void polyline(const std::vector<glm::vec3>& p, glm::vec4 color);
  /// A shaft from `from` to `to` with a four-barbed head a quarter of its length.
  void arrow(glm::vec3 from, glm::vec3 to, glm::vec4 color);
  /// The twelve edges of an axis-aligned box.
  void box(glm::vec3 lo, glm::vec3 hi, glm::vec4 color);
  /// Three short crossing lines of half-size `r` (a point marker).
  void cross(glm::vec3 c, float r, glm::vec4 color);
};

class OverlayRenderer {
 public:
  /// Needs a current OpenGL 3.3 core context (throws RenderError otherwise).
  OverlayRenderer();
  ~OverlayRenderer();
  OverlayRenderer(const OverlayRenderer&) = delete;
  OverlayRenderer& operator=(const OverlayRenderer&) = delete;

  /// Draws `hidden` depth-tested against what is drawn (the head hides
  /// lines behind it) and `on_top` over everything.
  void draw(const OverlayLines& hidden, const OverlayLines& on_top, const Camera& camera, int width, int height);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace loosehair::render
