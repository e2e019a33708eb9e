// The light's frame around the hair (method.md §7.2).
#include "light_frame.hpp"

#include "render_passes.hpp"

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>

namespace loosehair::render {

LightFrame lightFrame(const std::vector<glm::vec3>& points, const glm::vec3& light, const glm::vec3& fallback,
                      float widen, float extra, float pad) {
  LightFrame f;
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  for (const auto& p : points) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  if (points.empty()) lo = hi = fallback;
  lo -= glm::vec3(widen);
  hi += glm::vec3(widen);
  f.lo = lo;
  f.hi = hi;
  f.centre = 0.5f * (lo + hi);
  f.radius = 0.5f * glm::length(hi - lo) + extra;
  const glm::vec3 up = std::abs(light.y) < 0.95f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
  f.view = glm::lookAt(f.centre + light * (f.radius + 1.0f), f.centre, up);
  f.proj = glm::ortho(-f.radius, f.radius, -f.radius, f.radius, 0.01f, 2.0f * f.radius + 2.0f);
  float zmin = INFINITY, zmax = -INFINITY;
  for (const auto& p : points) {
    const float z = -(f.view * glm::vec4(p, 1.0f)).z;
    zmin = std::min(zmin, z);
    zmax = std::max(zmax, z);
  }
  if (points.empty()) zmin = zmax = 1.0f;
  zmin -= pad;
  zmax += pad;
  f.zmin = zmin;
  // the slices start at the hair nearest the light in each texel and deepen
  // with the square root of the depth (render/shaders/nearest_hair.glsl)
  f.dz = std::max(1e-4f, (zmax - zmin) / static_cast<float>(kSlices - 1));
  return f;
}

glm::mat4 LightFrame::coords(float offset) const {
  glm::mat4 a = glm::translate(glm::mat4(1.0f), glm::vec3(0.5f, 0.5f, 0.0f)) *
                glm::scale(glm::mat4(1.0f), glm::vec3(0.5f, 0.5f, 1.0f)) * proj;
  for (int c = 0; c < 4; ++c) a[c][2] = 0.0f;  // row 2: (-z_view - zmin) / dz - offset
  a[2][2] = -1.0f / dz;
  a[3][2] = -zmin / dz - offset;
  return a * view;
}

}  // namespace loosehair::render
