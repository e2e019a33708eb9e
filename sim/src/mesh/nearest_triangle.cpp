#include "mesh/nearest_triangle.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <utility>

namespace loosehair {

// Ericson's region tests (Real-Time Collision Detection, 5.1.5), written out.
glm::vec3 closestBarycentric(glm::vec3 p, glm::vec3 a, glm::vec3 b, glm::vec3 c) {
  const glm::vec3 ab = b - a, ac = c - a, ap = p - a;
  const float d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return {1, 0, 0};
  const glm::vec3 bp = p - b;
  const float d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return {0, 1, 0};
  const float vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const float v = d1 / (d1 - d3);
    return {1 - v, v, 0};
  }
  const glm::vec3 cp = p - c;
  const float d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return {0, 0, 1};
  const float vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const float w = d2 / (d2 - d6);
    return {1 - w, 0, w};
  }
  const float va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const float w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {0, 1 - w, w};
  }
  const float denom = 1.0f / (va + vb + vc);
  const float v = vb * denom, w = vc * denom;
  return {1 - v - w, v, w};
}

namespace {
constexpr std::uint32_t kLeafSize = 8;

float boxDistance2(glm::vec3 p, glm::vec3 lo, glm::vec3 hi) {
  const glm::vec3 d = glm::max(glm::max(lo - p, p - hi), glm::vec3(0.0f));
  return glm::dot(d, d);
}
}  // namespace

NearestTriangle::NearestTriangle(std::vector<glm::vec3> positions_in, std::vector<glm::u32vec3> triangles_in)
    : positions_(std::move(positions_in)), triangles_(std::move(triangles_in)) {
  const std::size_t n = triangles_.size();
  if (n == 0) return;
  std::vector<glm::vec3> centre(n), lo(n), hi(n);
  for (std::size_t k = 0; k < n; ++k) {
    const auto& t = triangles_[k];
    const glm::vec3 a = positions_[t.x], b = positions_[t.y], c = positions_[t.z];
    lo[k] = glm::min(a, glm::min(b, c));
    hi[k] = glm::max(a, glm::max(b, c));
    centre[k] = 0.5f * (lo[k] + hi[k]);
  }
  order_.resize(n);
  for (std::uint32_t k = 0; k < n; ++k) order_[k] = k;
  // top-down, split at the median of the longest axis of the centres
  struct Task {
    std::uint32_t node, first, count;
  };
  nodes_.push_back({});
  std::vector<Task> tasks{{0, 0, static_cast<std::uint32_t>(n)}};
  while (!tasks.empty()) {
    const Task task = tasks.back();
    tasks.pop_back();
    glm::vec3 blo(INFINITY), bhi(-INFINITY), clo(INFINITY), chi(-INFINITY);
    for (std::uint32_t e = task.first; e < task.first + task.count; ++e) {
      const std::uint32_t k = order_[e];
      blo = glm::min(blo, lo[k]);
      bhi = glm::max(bhi, hi[k]);
      clo = glm::min(clo, centre[k]);
      chi = glm::max(chi, centre[k]);
    }
    nodes_[task.node].lo = blo;
    nodes_[task.node].hi = bhi;
    if (task.count <= kLeafSize) {
      nodes_[task.node].first = task.first;
      nodes_[task.node].count = task.count;
      continue;
    }
    const glm::vec3 ext = chi - clo;
    const int axis = ext.x >= ext.y && ext.x >= ext.z ? 0 : ext.y >= ext.z ? 1 : 2;
    const std::uint32_t half = task.count / 2;
    auto begin = order_.begin() + task.first;
    std::nth_element(begin, begin + half, begin + task.count, [&](std::uint32_t a, std::uint32_t b) {
      return centre[a][axis] < centre[b][axis] || (centre[a][axis] == centre[b][axis] && a < b);
    });
    const auto left = static_cast<std::uint32_t>(nodes_.size());
    nodes_.push_back({});
    nodes_.push_back({});
    nodes_[task.node].first = left;
    nodes_[task.node].count = 0;
    tasks.push_back({left, task.first, half});
    tasks.push_back({left + 1, task.first + half, task.count - half});
  }
}

NearestTriangle::Hit NearestTriangle::nearest(glm::vec3 p) const {
  Hit best;
  if (nodes_.empty()) return best;
  float best2 = INFINITY;  // squared distance of `best`, for pruning
  auto test = [&](std::uint32_t k) {
    const auto& t = triangles_[k];
    const glm::vec3 a = positions_[t.x], b = positions_[t.y], c = positions_[t.z];
    const glm::vec3 l = closestBarycentric(p, a, b, c);
    const float d = glm::length(l.x * a + l.y * b + l.z * c - p);
    if (d < best.distance || (d == best.distance && k < best.triangle)) {
      best = {k, l, d};
      best2 = d * d;
    }
  };
  // depth first, nearer child first; a box is skipped only when it is
  // farther than the best distance (with a margin for rounding in the
  // squares), so a tie at the same distance is still visited
  std::uint32_t stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (boxDistance2(p, node.lo, node.hi) > best2 * (1.0f + 1e-5f)) continue;
    if (node.count > 0) {
      for (std::uint32_t e = node.first; e < node.first + node.count; ++e) test(order_[e]);
      continue;
    }
    const std::uint32_t a = node.first, b = node.first + 1;
    const float da = boxDistance2(p, nodes_[a].lo, nodes_[a].hi), db = boxDistance2(p, nodes_[b].lo, nodes_[b].hi);
    // push the farther first so the nearer is searched first
    stack[top++] = da <= db ? b : a;
    stack[top++] = da <= db ? a : b;
  }
  return best;
}

}  // namespace loosehair
