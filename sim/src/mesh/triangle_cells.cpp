#include "mesh/triangle_cells.hpp"

#include <glm/common.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace loosehair {

void TriangleCells::build(const std::vector<glm::vec3>& corners, float margin, std::size_t max_cells) {
  const std::size_t nt = corners.size() / 3;
  start_.assign(1, 0);
  list_.clear();
  dims_[0] = dims_[1] = dims_[2] = 0;
  cell_ = inv_cell_ = 0.0f;
  if (nt == 0) return;
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  double size_sum = 0;
  for (std::size_t t = 0; t < nt; ++t) {
    const glm::vec3 a = corners[3 * t], b = corners[3 * t + 1], c = corners[3 * t + 2];
    const glm::vec3 tl = glm::min(a, glm::min(b, c)), th = glm::max(a, glm::max(b, c));
    lo = glm::min(lo, tl);
    hi = glm::max(hi, th);
    const glm::vec3 e = th - tl;
    size_sum += static_cast<double>(std::max({e.x, e.y, e.z}));
  }
  if (!std::isfinite(lo.x + lo.y + lo.z + hi.x + hi.y + hi.z))
    throw std::invalid_argument("TriangleCells: a triangle corner is not finite");
  lo -= glm::vec3(margin);
  hi += glm::vec3(margin);
  const glm::vec3 extent = hi - lo;
  double cell = std::max(1.0 * size_sum / static_cast<double>(nt),
                         1e-6 * static_cast<double>(std::max({extent.x, extent.y, extent.z})) + 1e-9);
  auto count = [&](double s) {
    double n = 1;
    for (int a = 0; a < 3; ++a) n *= std::floor(static_cast<double>(extent[a]) / s) + 1.0;
    return n;
  };
  while (count(cell) > static_cast<double>(max_cells)) cell *= 1.25;
  cell_ = static_cast<float>(cell);
  inv_cell_ = 1.0f / cell_;
  origin_ = lo;
  for (int a = 0; a < 3; ++a) dims_[a] = static_cast<int>(std::floor(static_cast<double>(extent[a]) / cell)) + 1;
  const std::size_t cells =
      static_cast<std::size_t>(dims_[0]) * static_cast<std::size_t>(dims_[1]) * static_cast<std::size_t>(dims_[2]);
  // The cells a triangle's grown box overlaps, by the same rounding as
  // forEachNear (so a box that meets the query's meets a listed cell).
  auto range = [&](std::size_t t, int* l, int* h) {
    const glm::vec3 a = corners[3 * t], b = corners[3 * t + 1], c = corners[3 * t + 2];
    const glm::vec3 tl = glm::min(a, glm::min(b, c)) - glm::vec3(margin),
                    th = glm::max(a, glm::max(b, c)) + glm::vec3(margin);
    for (int k = 0; k < 3; ++k) {
      l[k] = std::clamp(static_cast<int>(std::floor((tl[k] - origin_[k]) * inv_cell_)), 0, dims_[k] - 1);
      h[k] = std::clamp(static_cast<int>(std::floor((th[k] - origin_[k]) * inv_cell_)), 0, dims_[k] - 1);
    }
  };
  std::vector<std::uint32_t> fill(cells + 1, 0);
  for (int pass = 0; pass < 2; ++pass) {
    for (std::size_t t = 0; t < nt; ++t) {
      int l[3], h[3];
      range(t, l, h);
      for (int z = l[2]; z <= h[2]; ++z)
        for (int y = l[1]; y <= h[1]; ++y)
          for (int x = l[0]; x <= h[0]; ++x) {
            const std::size_t c =
                (static_cast<std::size_t>(z) * static_cast<std::size_t>(dims_[1]) + static_cast<std::size_t>(y)) *
                    static_cast<std::size_t>(dims_[0]) +
                static_cast<std::size_t>(x);
            if (pass == 0)
              ++fill[c + 1];
            else
              list_[fill[c]++] = static_cast<std::uint32_t>(t);
          }
    }
    if (pass == 0) {
      for (std::size_t c = 0; c < cells; ++c) fill[c + 1] += fill[c];
      start_ = fill;
      list_.resize(fill[cells]);
    }
  }
}

}  // namespace loosehair
