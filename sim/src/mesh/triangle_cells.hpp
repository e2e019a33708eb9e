// The triangles near each cell of a uniform grid, for the exact distance's
// small searches (exact_distance.cpp): a point resting on a body asks for
// the nearest triangle within a ball of a fraction of a millimetre, which
// the cells answer from one or a few short lists where the hierarchy walks
// from its root.
#pragma once

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace loosehair {

class TriangleCells {
 public:
  /// `corners`: three a triangle. Each triangle is listed (by its index in
  /// `corners` / 3) in every cell its box, grown by `margin`, overlaps. The
  /// cell is the triangles' mean box size (twice that missed the L1 cache
  /// 1.4 times as often in the contact searches: docs/performance.md),
  /// coarser where more than `max_cells` cells would be needed.
  void build(const std::vector<glm::vec3>& corners, float margin, std::size_t max_cells);

  /// The largest ball radius forEachNear answers for: half a cell, so the
  /// ball's box overlaps at most two cells an axis.
  float reach() const { return 0.5f * cell_; }

  /// Calls f(k) for every triangle k listed in the cells that the box
  /// [p - r, p + r] overlaps (r <= reach(); some more than once): a
  /// superset of the triangles whose grown boxes meet it.
  template <class F>
  void forEachNear(const glm::vec3& p, float r, F&& f) const {
    int lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      const float l = (p[a] - r - origin_[a]) * inv_cell_, h = (p[a] + r - origin_[a]) * inv_cell_;
      // also false for NaN: nothing to visit
      if (!(h >= 0.0f && l < static_cast<float>(dims_[a]))) return;
      lo[a] = l > 0.0f ? static_cast<int>(l) : 0;
      hi[a] = h < static_cast<float>(dims_[a] - 1) ? static_cast<int>(h) : dims_[a] - 1;
    }
    for (int z = lo[2]; z <= hi[2]; ++z)
      for (int y = lo[1]; y <= hi[1]; ++y)
        for (int x = lo[0]; x <= hi[0]; ++x) {
          const std::size_t c =
              (static_cast<std::size_t>(z) * static_cast<std::size_t>(dims_[1]) + static_cast<std::size_t>(y)) *
                  static_cast<std::size_t>(dims_[0]) +
              static_cast<std::size_t>(x);
          for (std::uint32_t e = start_[c]; e < start_[c + 1]; ++e) f(list_[e]);
        }
  }

 private:
  glm::vec3 origin_{0.0f};
  float cell_ = 0.0f, inv_cell_ = 0.0f;
  int dims_[3] = {0, 0, 0};
  std::vector<std::uint32_t> start_;  // per cell, into list_ (one more than cells)
  std::vector<std::uint32_t> list_;   // triangle indices, cell by cell
};

}  // namespace loosehair
