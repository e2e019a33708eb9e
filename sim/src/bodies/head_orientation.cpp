#include "bodies/head_orientation.hpp"

#include <glm/common.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace loosehair {

std::vector<std::string> headOrientationWarnings(const TriangleMesh& mesh, const std::string& field) {
  std::vector<std::string> out;
  if (mesh.vertices.empty()) return out;
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  for (const glm::vec3& v : mesh.vertices) {
    lo = glm::min(lo, v);
    hi = glm::max(hi, v);
  }
  const glm::vec3 ext = hi - lo;
  char buf[320];
  if (ext.z > 1.25f * ext.y || ext.x > 1.6f * ext.y) {
    std::snprintf(buf, sizeof buf,
                  "%s: the mesh is %.3g m tall (y), %.3g m wide (x) and %.3g m deep (z): it seems to lie "
                  "on its side; if its up axis is not +y, set %s.up (for example \"+z\") and %s.front",
                  field.c_str(), static_cast<double>(ext.y), static_cast<double>(ext.x), static_cast<double>(ext.z),
                  field.c_str(), field.c_str());
    out.emplace_back(buf);
    return out;
  }
  // Width (x extent) of the slice just below the top against the widest
  // slice: a cranium's dome is narrow there (about 0.45 of a head's width 3%
  // of the height down, 0.2 of a bust's), a cut neck or a bust's base is not.
  constexpr int kSlices = 100;
  std::vector<float> slo(kSlices, INFINITY), shi(kSlices, -INFINITY);
  const float dy = ext.y / kSlices;
  if (!(dy > 0.0f)) return out;
  for (const glm::vec3& v : mesh.vertices) {
    const int s = std::clamp(static_cast<int>((hi.y - v.y) / dy), 0, kSlices - 1);
    slo[static_cast<std::size_t>(s)] = std::min(slo[static_cast<std::size_t>(s)], v.x);
    shi[static_cast<std::size_t>(s)] = std::max(shi[static_cast<std::size_t>(s)], v.x);
  }
  // Slices between the vertices of long triangles: the edges' crossings of
  // each slice's middle count as well.
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) {
      const glm::vec3 a = mesh.vertices[t[k]], b = mesh.vertices[t[(k + 1) % 3]];
      if (a.y == b.y) continue;
      const float y0 = std::min(a.y, b.y), y1 = std::max(a.y, b.y);
      const int s0 = std::clamp(static_cast<int>((hi.y - y1) / dy - 0.5f), 0, kSlices - 1);
      const int s1 = std::clamp(static_cast<int>((hi.y - y0) / dy + 0.5f), 0, kSlices - 1);
      for (int s = s0; s <= s1; ++s) {
        const float y = hi.y - (static_cast<float>(s) + 0.5f) * dy;
        if (y < y0 || y > y1) continue;
        const float x = a.x + (b.x - a.x) * (y - a.y) / (b.y - a.y);
        slo[static_cast<std::size_t>(s)] = std::min(slo[static_cast<std::size_t>(s)], x);
        shi[static_cast<std::size_t>(s)] = std::max(shi[static_cast<std::size_t>(s)], x);
      }
    }
  float widest = 0, top = 0;
  for (int s = 0; s < kSlices; ++s) {
    const float w = shi[static_cast<std::size_t>(s)] - slo[static_cast<std::size_t>(s)];
    if (!(w > 0.0f)) continue;
    widest = std::max(widest, w);
    if (s == 2) top = w;
  }
  // A neck on top: the widths from 10% to 40% of the height down stay
  // within 20% of each other (a cranium widens there) and the widest slice
  // lies in the lower half.
  float band_lo = INFINITY, band_hi = 0;
  int widest_at = 0;
  for (int s = 0; s < kSlices; ++s) {
    const float w = shi[static_cast<std::size_t>(s)] - slo[static_cast<std::size_t>(s)];
    if (!(w > 0.0f)) continue;
    if (w >= widest) widest_at = s;
    if (s >= 10 && s <= 40) {
      band_lo = std::min(band_lo, w);
      band_hi = std::max(band_hi, w);
    }
  }
  const bool neck_on_top = widest_at > kSlices / 2 && band_hi > 0.0f && band_hi < 1.2f * band_lo;
  if (widest > 0.0f && (top > 0.6f * widest || neck_on_top)) {
    std::snprintf(buf, sizeof buf,
                  "%s: the top of the mesh looks like a neck or a bust's base, not a cranium (%s): if it "
                  "stands upside down, set %s.up (for example \"-y\")",
                  field.c_str(),
                  neck_on_top ? "its upper half is as wide throughout as a neck, its widest part below"
                              : "flat and wide just below the top",
                  field.c_str());
    out.emplace_back(buf);
  }
  return out;
}

}  // namespace loosehair
