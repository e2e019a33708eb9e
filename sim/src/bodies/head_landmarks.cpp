// Heights on a head mesh (loosehair/head_landmarks.hpp).
#include "loosehair/head_landmarks.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace loosehair {

HeadHeights measureHeadHeights(const TriangleMesh& m) {
  if (m.vertices.empty()) throw MeshError("head heights: the mesh has no vertices");
  float ymin = INFINITY, ymax = -INFINITY;
  for (const auto& v : m.vertices) ymin = std::min(ymin, v.y), ymax = std::max(ymax, v.y);
  if (!(ymax - ymin > 0.0f) || !std::isfinite(ymax - ymin))
    throw MeshError("head heights: the mesh is flat or not finite");
  constexpr float kSlice = 0.005f;
  const int n = static_cast<int>(std::min(100000.0f, (ymax - ymin) / kSlice)) + 1;
  const auto un = static_cast<std::size_t>(n);
  std::vector<float> lo(un, INFINITY), hi(un, -INFINITY), front(un, -INFINITY);
  for (const auto& v : m.vertices) {
    const auto k = static_cast<std::size_t>(std::clamp(static_cast<int>((ymax - v.y) / kSlice), 0, n - 1));
    lo[k] = std::min(lo[k], v.x);
    hi[k] = std::max(hi[k], v.x);
    if (std::abs(v.x) < 0.02f) front[k] = std::max(front[k], v.z);
  }
  auto y = [&](std::size_t k) { return ymax - (static_cast<float>(k) + 0.5f) * kSlice; };
  auto width = [&](std::size_t k) { return hi[k] > lo[k] ? hi[k] - lo[k] : 0.0f; };
  HeadHeights h;
  h.top = ymax;
  const auto nose = static_cast<std::size_t>(std::max_element(front.begin(), front.end()) - front.begin());
  if (!std::isfinite(front[nose])) throw MeshError("head heights: no face found (no vertex within 2 cm of x = 0)");
  float cranium = 0;
  for (std::size_t k = 0; k < nose / 2; ++k) cranium = std::max(cranium, width(k));
  if (!(cranium > 0.0f)) throw MeshError("head heights: no cranium found above the nose (the face is at the top)");
  std::size_t first = un, last = un;
  for (std::size_t k = nose / 3; k < un; ++k) {
    if (width(k) > 1.04f * cranium) {
      if (first == un) first = k;
      last = k;
    } else if (first != un) {
      break;
    }
  }
  if (first == un) throw MeshError("head heights: no part of the head is wider than its cranium (no ears found)");
  h.ear_top = y(first);
  h.ear_bottom = y(last);
  h.chin = y(un - 1);
  for (std::size_t k = nose + 1; k < un; ++k)
    if (front[k] < front[k - 1] - 0.02f) {
      h.chin = y(k - 1);
      break;
    }
  h.brows = h.ear_top + 0.3f * (h.top - h.ear_top);
  return h;
}

}  // namespace loosehair
