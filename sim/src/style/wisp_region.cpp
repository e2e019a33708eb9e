#include "style/wisp_region.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace loosehair {

bool polygonContains(const std::vector<glm::vec2>& poly, glm::vec2 p) {
  bool inside = false;
  const std::size_t n = poly.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const glm::vec2 a = poly[i], b = poly[j];
    if ((a.y > p.y) != (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x) inside = !inside;
  }
  return inside;
}

bool regionContains(const WispRegion& region, const HeadModel& head, glm::vec2 uv) {
  for (const auto& poly : region.polygons)
    if (polygonContains(poly, uv)) return true;
  if (!region.triangles.empty()) {
    const std::uint32_t t = head.scalpTriangleAt(uv);
    if (std::binary_search(region.triangles.begin(), region.triangles.end(), t)) return true;
  }
  return false;
}

std::vector<std::uint32_t> regionTriangles(const WispRegion& region, const HeadModel& head) {
  const ScalpTriangles& s = head.scalpTriangles();
  std::vector<std::uint32_t> out;
  for (std::uint32_t t : region.triangles)
    if (t < s.triangles.size()) out.push_back(t);
  for (const auto& polygon : region.polygons) {
    if (polygon.empty()) continue;
    glm::vec2 lo = polygon.front(), hi = polygon.front();
    for (const glm::vec2 q : polygon) {
      lo = glm::min(lo, q);
      hi = glm::max(hi, q);
    }
    // a triangle that meets the polygon overlaps its box
    for (std::uint32_t t : head.scalpTrianglesNear(lo, hi)) {
      const auto tr = s.triangles[t];
      const glm::vec2 a = s.uvs[tr.x], b = s.uvs[tr.y], c = s.uvs[tr.z];
      bool hit = polygonContains(polygon, a) || polygonContains(polygon, b) || polygonContains(polygon, c) ||
                 polygonContains(polygon, (a + b + c) / 3.0f);
      for (std::size_t k = 0; k < polygon.size() && !hit; ++k) {  // a corner of a small polygon inside the triangle
        const glm::vec2 e1 = b - a, e2 = c - a, d = polygon[k] - a;
        const float det = e1.x * e2.y - e1.y * e2.x;
        if (det == 0.0f) continue;
        const float l1 = (d.x * e2.y - d.y * e2.x) / det, l2 = (e1.x * d.y - e1.y * d.x) / det;
        hit = l1 >= 0 && l2 >= 0 && l1 + l2 <= 1;
      }
      if (hit) out.push_back(t);
    }
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

namespace {
// Points of each triangle at which the region is probed: a 4x4 lattice of
// barycentric points (deterministic, so areas and roots repeat exactly).
template <class F>
void probe(const HeadModel& head, std::uint32_t t, F&& f) {
  const ScalpTriangles& s = head.scalpTriangles();
  const auto tr = s.triangles[t];
  constexpr int kN = 4;
  for (int i = 0; i < kN; ++i)
    for (int j = 0; i + j < kN; ++j) {
      const float l1 = (static_cast<float>(i) + 1.0f / 3.0f) / kN, l2 = (static_cast<float>(j) + 1.0f / 3.0f) / kN;
      const glm::vec2 uv = (1.0f - l1 - l2) * s.uvs[tr.x] + l1 * s.uvs[tr.y] + l2 * s.uvs[tr.z];
      f(uv);
    }
}
constexpr double kProbes = 10.0;  // lattice points per triangle (4 + 3 + 2 + 1)
}  // namespace

double regionArea(const WispRegion& region, const HeadModel& head) {
  const ScalpTriangles& s = head.scalpTriangles();
  double area = 0;
  for (std::uint32_t t : regionTriangles(region, head)) {
    if (std::binary_search(region.triangles.begin(), region.triangles.end(), t)) {
      area += s.areas[t];
      continue;
    }
    int in = 0;
    probe(head, t, [&](glm::vec2 uv) { in += regionContains(region, head, uv) ? 1 : 0; });
    area += s.areas[t] * in / kProbes;
  }
  if (area == 0.0 && !region.polygons.empty()) {
    // polygons smaller than the probe lattice: their (u, v) area scaled by
    // the scalp's area per (u, v) area at each polygon's centre
    for (const auto& poly : region.polygons) {
      double a2 = 0;
      glm::vec2 c(0.0f);
      for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
        a2 += static_cast<double>(poly[j].x) * poly[i].y - static_cast<double>(poly[i].x) * poly[j].y;
        c += poly[i];
      }
      c /= static_cast<float>(poly.size());
      const auto tr = s.triangles[head.scalpTriangleAt(c)];
      const glm::vec2 e1 = s.uvs[tr.y] - s.uvs[tr.x], e2 = s.uvs[tr.z] - s.uvs[tr.x];
      const double uv_area = 0.5 * std::abs(static_cast<double>(e1.x) * e2.y - static_cast<double>(e1.y) * e2.x);
      if (uv_area > 0.0) area += 0.5 * std::abs(a2) * s.areas[head.scalpTriangleAt(c)] / uv_area;
    }
  }
  return area;
}

glm::vec2 regionRoot(const WispRegion& region, const HeadModel& head) {
  const ScalpTriangles& s = head.scalpTriangles();
  glm::dvec2 sum(0.0);
  double weight = 0;
  std::vector<glm::vec2> inside;
  for (std::uint32_t t : regionTriangles(region, head)) {
    const double w = s.areas[t] / kProbes;
    probe(head, t, [&](glm::vec2 uv) {
      if (!regionContains(region, head, uv)) return;
      sum += w * glm::dvec2(uv);
      weight += w;
      inside.push_back(uv);
    });
  }
  if (inside.empty()) {  // a polygon smaller than the probe lattice
    for (const auto& poly : region.polygons)
      for (const glm::vec2 q : poly) inside.push_back(q);
    if (inside.empty()) return glm::vec2(0.5f);
    glm::vec2 c(0.0f);
    for (const glm::vec2 q : inside) c += q;
    return glm::clamp(c / static_cast<float>(inside.size()), glm::vec2(0.0f), glm::vec2(1.0f));
  }
  const glm::vec2 centre(sum / weight);
  if (regionContains(region, head, centre)) return centre;
  glm::vec2 best = inside.front();
  for (const glm::vec2 q : inside)
    if (glm::length(q - centre) < glm::length(best - centre)) best = q;
  return best;
}

}  // namespace loosehair
