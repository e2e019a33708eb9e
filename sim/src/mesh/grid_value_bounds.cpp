// Far grid values checked against the triangles (grid_value_bounds.hpp).
#include "mesh/grid_value_bounds.hpp"

#include "util/parallel.hpp"

#include <numeric>
#include <vector>

namespace loosehair {

std::size_t boundFarValues(const ExactDistance& exact, const GridValues& grid, float exact_from, float allowance,
                           int threads) {
  const auto sx = static_cast<std::size_t>(grid.dims.x), sy = static_cast<std::size_t>(grid.dims.y),
             sz = static_cast<std::size_t>(grid.dims.z);
  std::vector<std::size_t> changed(sz, 0);  // per slab, summed in order below
  parallel::forEach(threads, sz, [&](std::size_t k) {
    for (std::size_t j = 0; j < sy; ++j)
      for (std::size_t i = 0; i < sx; ++i) {
        const std::size_t at = (k * sy + j) * sx + i;
        const float v = grid.value[at];
        // Inside, the conversion's value is minus the distance to some
        // triangle, never above the exact one; near the surface it is exact.
        if (!(v >= exact_from)) continue;
        const glm::vec3 c = grid.lower + grid.voxel * glm::vec3(glm::uvec3(i, j, k));
        // A triangle nearer than v - allowance (or the voxel inside a part
        // whose surface is that near) means the value overstates the
        // distance by more. Most balls hold no triangle, and the search
        // ends at the hierarchy's top boxes: 0.12-0.14 s a bundled mesh. (A
        // search out to v, which would also catch a wrong sign with the
        // right magnitude, cost 1.1 s more on the head; beyond the exact
        // band the conversion's sign comes from flooding the outside, which
        // a closed mesh makes sure of.)
        const std::int32_t seed = grid.nearest[at];
        ExactDistance::Nearest near{};
        if (!exact.nearest(c, v - allowance, &seed, seed >= 0 ? 1 : 0, near)) continue;
        if (!(v - near.signed_distance > allowance)) continue;
        grid.value[at] = near.signed_distance;
        grid.nearest[at] = static_cast<std::int32_t>(near.triangle);
        ++changed[k];
      }
  });
  return std::accumulate(changed.begin(), changed.end(), std::size_t{0});
}

}  // namespace loosehair
