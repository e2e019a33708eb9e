// The orbit camera (no GL: the viewer's picking and the tests use it too).
#include "loosehair/render/renderer.hpp"

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/trigonometric.hpp>

#include <cmath>

namespace loosehair::render {

Camera Camera::preset(const std::string& name) {
  Camera c;
  if (name == "front")
    c.yaw_deg = 0;
  else if (name == "side")
    c.yaw_deg = 90;
  else if (name == "back")
    c.yaw_deg = 180;
  else if (name == "three-quarter") {
    c.yaw_deg = 35;
    c.pitch_deg = 12;
  } else
    throw RenderError("unknown camera preset \"" + name + "\" (use front, side, back or three-quarter)");
  return c;
}

glm::vec3 Camera::eye() const {
  const float yaw = glm::radians(yaw_deg), pitch = glm::radians(pitch_deg);
  return target +
         distance * glm::vec3(std::sin(yaw) * std::cos(pitch), std::sin(pitch), std::cos(yaw) * std::cos(pitch));
}

glm::vec3 Camera::keyLight() const {
  const float yaw = glm::radians(yaw_deg);
  const glm::vec3 l = RenderSettings{}.light_direction;  // the front camera's
  const float c = std::cos(yaw), s = std::sin(yaw);
  // R_y(yaw) takes the front camera's eye direction (0, 0, 1) to eye()'s
  return glm::normalize(glm::vec3(c * l.x + s * l.z, l.y, -s * l.x + c * l.z));
}

glm::mat4 Camera::view() const { return glm::lookAt(eye(), target, glm::vec3(0, 1, 0)); }

glm::mat4 Camera::projection(float aspect) const {
  glm::mat4 p = glm::perspective(glm::radians(fov_deg), aspect, near_plane, far_plane);
  // x_ndc += shift_x: clip x gains shift_x * w, and w = -z in eye space
  p[2][0] -= shift_x;
  return p;
}

Ray Camera::ray(double x, double y, int width, int height) const {
  const float w = static_cast<float>(width > 0 ? width : 1), h = static_cast<float>(height > 0 ? height : 1);
  const glm::mat4 inv = glm::inverse(projection(w / h) * view());
  // pixel centre to normalised device coordinates (y up)
  const float nx = 2.0f * static_cast<float>(x) / w - 1.0f, ny = 1.0f - 2.0f * static_cast<float>(y) / h;
  const glm::vec4 near_p = inv * glm::vec4(nx, ny, -1.0f, 1.0f), far_p = inv * glm::vec4(nx, ny, 1.0f, 1.0f);
  const glm::vec3 a = glm::vec3(near_p) / near_p.w, b = glm::vec3(far_p) / far_p.w;
  return Ray{a, glm::normalize(b - a)};
}

glm::vec2 Camera::pixel(glm::vec3 p, int width, int height) const {
  const float w = static_cast<float>(width > 0 ? width : 1), h = static_cast<float>(height > 0 ? height : 1);
  const glm::vec4 clip = projection(w / h) * view() * glm::vec4(p, 1.0f);
  const float nx = clip.x / clip.w, ny = clip.y / clip.w;
  return {0.5f * (nx + 1.0f) * w, 0.5f * (1.0f - ny) * h};
}

}  // namespace loosehair::render
