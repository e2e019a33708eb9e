#include "hair_chain.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace loosehair {

HairChain::HairChain(const ConnectionSet& c, std::span<const std::uint8_t> is_root, float h1) {
  const std::size_t n = is_root.size();
  constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  parent_.assign(n, kNone);
  reach_.assign(n, 0.0f);
  // breadth-first from the roots: a particle's depth is one more than that
  // of the first root-side partner that reaches it
  std::vector<std::uint32_t> depth(n, kNone), frontier, next;
  for (std::uint32_t i = 0; i < n; ++i)
    if (is_root[i]) {
      depth[i] = 0;
      frontier.push_back(i);
    }
  for (std::uint32_t d = 1; !frontier.empty(); ++d) {
    next.clear();
    for (std::uint32_t j : frontier)
      for (std::uint32_t e = c.begin(j); e < c.end(j); ++e) {
        const std::uint32_t i = c.partner[e];
        if (c.tip_side[e] && depth[i] == kNone) {
          depth[i] = d;
          next.push_back(i);
        }
      }
    // (the order within a depth is the particles' own: deterministic)
    std::sort(next.begin(), next.end());
    for (std::uint32_t i : next) {
      // the nearest root-side partner of a lower depth
      float best = std::numeric_limits<float>::infinity();
      for (std::uint32_t e = c.begin(i); e < c.tipBegin(i); ++e) {
        const std::uint32_t j = c.partner[e];
        if (depth[j] < d && c.rest_length[e] < best) {
          best = c.rest_length[e];
          parent_[i] = j;
        }
      }
      if (parent_[i] == kNone) continue;  // (a tip-side entry reached it; cannot happen with symmetric sides)
      reach_[i] = std::max(kSupportFraction * 2.0f * h1, best);
      order_.push_back(i);
    }
    frontier.swap(next);
  }
}

}  // namespace loosehair
