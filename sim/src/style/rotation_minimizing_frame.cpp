#include "style/rotation_minimizing_frame.hpp"

#include <glm/geometric.hpp>

#include <cmath>

namespace loosehair {
namespace {

glm::vec3 unitOr(glm::vec3 v, glm::vec3 fallback) {
  const float len = glm::length(v);
  return len > 1e-20f ? v / len : fallback;
}

glm::vec3 anyOrthogonal(glm::vec3 t) {
  const glm::vec3 a = std::abs(t.x) < 0.6f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
  return glm::normalize(a - glm::dot(a, t) * t);
}

}  // namespace

std::vector<glm::vec3> polylineTangents(const std::vector<glm::vec3>& p) {
  const std::size_t n = p.size();
  std::vector<glm::vec3> t(n, glm::vec3(0, 0, 1));
  if (n < 2) return t;
  for (std::size_t i = 0; i < n; ++i) {
    const glm::vec3 a = p[i == 0 ? 0 : i - 1], b = p[i + 1 == n ? n - 1 : i + 1];
    t[i] = unitOr(b - a, i > 0 ? t[i - 1] : glm::vec3(0, 0, 1));
  }
  return t;
}

std::vector<CurveFrame> rotationMinimizingFrames(const std::vector<glm::vec3>& p, glm::vec3 reference) {
  const std::vector<glm::vec3> t = polylineTangents(p);
  const std::size_t n = p.size();
  std::vector<CurveFrame> f(n);
  if (n == 0) return f;
  glm::vec3 r = reference - glm::dot(reference, t[0]) * t[0];
  r = glm::length(r) > 1e-6f ? glm::normalize(r) : anyOrthogonal(t[0]);
  f[0] = {t[0], r, glm::cross(t[0], r)};
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const glm::vec3 v1 = p[i + 1] - p[i];
    const float c1 = glm::dot(v1, v1);
    glm::vec3 rl = f[i].normal, tl = f[i].tangent;
    if (c1 > 0.0f) {  // first reflection, in the chord's bisecting plane
      rl -= (2.0f / c1) * glm::dot(v1, rl) * v1;
      tl -= (2.0f / c1) * glm::dot(v1, tl) * v1;
    }
    const glm::vec3 v2 = t[i + 1] - tl;
    const float c2 = glm::dot(v2, v2);
    if (c2 > 1e-24f) rl -= (2.0f / c2) * glm::dot(v2, rl) * v2;  // second: tl onto t[i+1]
    // re-orthonormalise against rounding drift over long curves
    rl -= glm::dot(rl, t[i + 1]) * t[i + 1];
    rl = glm::length(rl) > 1e-6f ? glm::normalize(rl) : anyOrthogonal(t[i + 1]);
    f[i + 1] = {t[i + 1], rl, glm::cross(t[i + 1], rl)};
  }
  return f;
}

}  // namespace loosehair
