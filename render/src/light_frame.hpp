// The light's frame (method.md §7.2): an orthographic view along -light
// around the hair, and the depth unit of the opacity slices.
#pragma once

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <vector>

namespace loosehair::render {

struct LightFrame {
  glm::vec3 lo{0.0f}, hi{0.0f};  // the hair's box (world)
  glm::vec3 centre{0.0f};
  float radius = 0.0f;  // of the orthographic view
  glm::mat4 view{1.0f}, proj{1.0f};
  float zmin = 0.0f;  // the hair nearest the light (depth along it)
  float dz = 0.0f;    // the depth unit: a 15th of the hair's extent along the light

  /// world -> (s, t, depth in slices - offset): the opacity lookups (with
  /// the shadow offset) and the light pass (offset 0); one affine map.
  glm::mat4 coords(float offset) const;
};

/// The frame around `points` (their box widened by `widen`; the camera's
/// target where there are none), the view's radius `extra` beyond the box,
/// the depth range padded by `pad`.
LightFrame lightFrame(const std::vector<glm::vec3>& points, const glm::vec3& light, const glm::vec3& fallback,
                      float widen, float extra, float pad);

}  // namespace loosehair::render
