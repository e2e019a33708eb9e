#include "solver/hair_chain.hpp"

#include <glm/common.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace loosehair {

HairChain::HairChain(const ConnectionSet& c, std::span<const std::uint8_t> is_root, std::span<const float> s,
                     std::span<const glm::vec3> root_point, float h1) {
  const std::size_t n = is_root.size();
  support_reach_ = kSupportFraction * 2.0f * h1;
  root_.assign(root_point.begin(), root_point.end());
  // a particle's candidates: its partners nearer the root by arc length
  // (following them ends at a root, s falling all the way)
  first_.assign(n + 1, 0);
  for (std::uint32_t i = 0; i < n; ++i) {
    if (!is_root[i])
      for (std::uint32_t e = c.begin(i); e < c.end(i); ++e) {
        const std::uint32_t j = c.partner[e];
        if (s[j] < s[i]) {
          candidate_.push_back(j);
          reach_.push_back(std::max(support_reach_, c.rest_length[e]));
        }
      }
    first_[i + 1] = static_cast<std::uint32_t>(candidate_.size());
    if (first_[i + 1] > first_[i]) order_.push_back(i);
  }
  // each particle's root region: its candidates' roots included
  region2_.assign(n, (kRegionReaches * support_reach_) * (kRegionReaches * support_reach_));
  for (std::uint32_t i = 0; i < n; ++i)
    for (std::uint32_t k = first_[i]; k < first_[i + 1]; ++k) {
      const glm::vec3 d = root_[candidate_[k]] - root_[i];
      region2_[i] = std::max(region2_[i], glm::dot(d, d));
    }
  // what may hold a particle: a root, or a particle the chain holds itself
  holds_.assign(n, 0);
  for (std::uint32_t i = 0; i < n; ++i) holds_[i] = is_root[i] || first_[i + 1] > first_[i];
  // by arc length: whatever is nearer the root is placed first
  std::stable_sort(order_.begin(), order_.end(), [&](std::uint32_t a, std::uint32_t b) { return s[a] < s[b]; });
}

namespace {

std::uint64_t cellKey(glm::ivec3 c) {
  // 21 bits an axis, offset to be positive (cells of centimetres: 20 km)
  const auto u = [](int v) { return static_cast<std::uint64_t>(v + (1 << 20)) & 0x1fffff; };
  return (u(c.x) << 42) | (u(c.y) << 21) | u(c.z);
}

glm::ivec3 cellOf(const glm::vec3& p, float inv) { return glm::ivec3(glm::floor(p * inv)); }

}  // namespace

void HairChain::makeGrid(std::span<const glm::vec3> x) const {
  const float inv = 1.0f / support_reach_;
  auto& keyed = keyed_;
  keyed.resize(x.size());
  for (std::uint32_t i = 0; i < x.size(); ++i) keyed[i] = {cellKey(cellOf(x[i], inv)), i};
  std::sort(keyed.begin(), keyed.end());
  cell_key_.resize(keyed.size());
  cell_particle_.resize(keyed.size());
  for (std::size_t k = 0; k < keyed.size(); ++k) {
    cell_key_[k] = keyed[k].first;
    cell_particle_[k] = keyed[k].second;
  }
}

template <class Visit>
void HairChain::forEachHolder(std::span<const glm::vec3> x, std::span<const float> s, std::uint32_t i, int cells,
                              const Visit& visit) const {
  const glm::ivec3 c = cellOf(x[i], 1.0f / support_reach_);
  for (int dz = -cells; dz <= cells; ++dz)
    for (int dy = -cells; dy <= cells; ++dy)
      for (int dx = -cells; dx <= cells; ++dx) {
        const std::uint64_t key = cellKey(c + glm::ivec3(dx, dy, dz));
        auto it = std::lower_bound(cell_key_.begin(), cell_key_.end(), key);
        for (; it != cell_key_.end() && *it == key; ++it) {
          const std::uint32_t j = cell_particle_[static_cast<std::size_t>(it - cell_key_.begin())];
          if (j == i || !(s[j] < s[i]) || !holds_[j] || !sameRegion(i, j)) continue;
          const glm::vec3 d = x[j] - x[i];
          if (visit(j, glm::dot(d, d))) return;
        }
      }
}

bool HairChain::nearerHairWithin(std::span<const glm::vec3> x, std::span<const float> s, std::uint32_t i) const {
  const float r2 = support_reach_ * support_reach_;
  bool found = false;
  forEachHolder(x, s, i, 1, [&](std::uint32_t, float d2) { return found = d2 < r2; });
  return found;
}

bool HairChain::nearestNearerHair(std::span<const glm::vec3> x, std::span<const float> s, std::uint32_t i,
                                  std::uint32_t& nearest) const {
  float best = 4.0f * support_reach_ * support_reach_;
  bool found = false;
  forEachHolder(x, s, i, 2, [&](std::uint32_t j, float d2) {
    // ties by index: the same answer whatever the cell order
    if (d2 < best || (d2 == best && found && j < nearest)) best = d2, nearest = j, found = true;
    return false;
  });
  return found;
}

}  // namespace loosehair
