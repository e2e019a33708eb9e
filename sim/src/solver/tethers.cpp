// Tethers: tethers.hpp.
#include "solver/tethers.hpp"

#include "util/parallel.hpp"
#include "solver/tether.hpp"

#include <cassert>

namespace loosehair {

void applyTethers(float slack, std::span<const std::uint8_t> is_root, std::span<const glm::vec3> root_point,
                  std::span<const float> arc_length, std::span<const glm::vec3> tie_point,
                  std::span<const float> tie_reach, std::span<glm::vec3> position, int threads) {
  const std::size_t n = position.size();
  assert(is_root.size() == n && root_point.size() == n && arc_length.size() == n);
  assert(tie_point.size() == tie_reach.size() && (tie_reach.empty() || tie_reach.size() == n));
  const float scale = 1.0f + slack;
  const bool ties = !tie_reach.empty();
  parallel::run(threads, [&] {
    const auto [first, last] = parallel::share(n);
    for (std::size_t i = first; i < last; ++i) {
      if (is_root[i]) continue;
      glm::vec3 x = tether::within(position[i], root_point[i], scale * arc_length[i]);
      if (ties && tie_reach[i] >= 0.0f) x = tether::within(x, tie_point[i], scale * tie_reach[i]);
      position[i] = x;
    }
  });
}

}  // namespace loosehair
