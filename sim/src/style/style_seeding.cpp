#include "style/style_seeding.hpp"

#include "util/random.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace loosehair {
namespace {

struct Candidate {
  std::uint32_t strand;
  float s;
};

std::int64_t key(glm::ivec3 c) {
  return (static_cast<std::int64_t>(c.x) * 73856093) ^ (static_cast<std::int64_t>(c.y) * 19349663) ^
         (static_cast<std::int64_t>(c.z) * 83492791);
}

}  // namespace

StrandSeeding seedFromStrands(const StrandSet& set, int target, std::uint64_t seed, float root_depth_scale) {
  StrandSeeding out;
  const std::size_t ns = set.size();
  if (ns == 0 || target < 1) return out;
  // arc lengths of every strand point
  std::vector<float> arc(set.points.size(), 0.0f);
  double total_length = 0;
  for (std::size_t k = 0; k < ns; ++k) {
    for (std::uint32_t j = set.first[k] + 1; j < set.first[k + 1]; ++j)
      arc[j] = arc[j - 1] + glm::length(set.points[j] - set.points[j - 1]);
    total_length += arc[set.first[k + 1] - 1];
  }
  // a first radius: the strands as a volume of about total_length * r^2 per sample
  float radius = static_cast<float>(std::sqrt(total_length * 0.02 / target));  // refined below
  radius = std::max(radius, 1e-4f);
  auto point = [&](std::uint32_t k, float s, glm::vec3& dir) {
    const std::uint32_t a = set.first[k], b = set.first[k + 1];
    if (s <= 0.0f) {
      dir = glm::normalize(set.points[a + 1] - set.points[a]);
      return set.points[a] + s * dir;
    }
    // the segment holding s (binary search in the strand's arc lengths)
    const auto it = std::upper_bound(arc.begin() + a, arc.begin() + b, s);
    std::uint32_t j = static_cast<std::uint32_t>(it - arc.begin());
    j = std::clamp<std::uint32_t>(j, a + 1, b - 1);
    const float seg = arc[j] - arc[j - 1];
    const float t = seg > 0.0f ? std::clamp((s - arc[j - 1]) / seg, 0.0f, 1.0f) : 0.0f;
    dir = set.points[j] - set.points[j - 1];
    dir = glm::length(dir) > 0.0f ? glm::normalize(dir) : glm::vec3(0, -1, 0);
    return set.points[j - 1] + t * (set.points[j] - set.points[j - 1]);
  };
  double best_error = INFINITY;
  for (int round = 0; round < 8; ++round) {
    const float depth = root_depth_scale * radius;
    // the candidate sequence: fixed for the seed, scaled to this round's depth
    Random rng(seed);
    std::vector<double> cdf(ns);
    double sum = 0;
    for (std::size_t k = 0; k < ns; ++k) cdf[k] = sum += arc[set.first[k + 1] - 1] + depth;
    const std::size_t candidates = static_cast<std::size_t>(target) * 16 + 64;
    std::unordered_map<std::int64_t, std::vector<std::uint32_t>> grid;
    std::vector<StrandSample> kept;
    kept.reserve(static_cast<std::size_t>(target) * 2);
    for (std::size_t c = 0; c < candidates; ++c) {
      const double x = rng.uniform() * sum;
      const auto k = static_cast<std::uint32_t>(std::min<std::size_t>(
          static_cast<std::size_t>(std::upper_bound(cdf.begin(), cdf.end(), x) - cdf.begin()), ns - 1));
      const float len = arc[set.first[k + 1] - 1];
      const float s = static_cast<float>(rng.uniform()) * (len + depth) - depth;
      glm::vec3 dir;
      const glm::vec3 p = point(k, s, dir);
      const glm::ivec3 cell(glm::floor(p / radius));
      bool free = true;
      for (int dz = -1; dz <= 1 && free; ++dz)
        for (int dy = -1; dy <= 1 && free; ++dy)
          for (int dx = -1; dx <= 1 && free; ++dx) {
            const auto it = grid.find(key(cell + glm::ivec3(dx, dy, dz)));
            if (it == grid.end()) continue;
            for (std::uint32_t q : it->second)
              if (glm::length(kept[q].position - p) < radius) {
                free = false;
                break;
              }
          }
      if (!free) continue;
      grid[key(cell)].push_back(static_cast<std::uint32_t>(kept.size()));
      kept.push_back({p, dir, set.root_uv[k], s, set.points[set.first[k]], k});
    }
    const double ratio = static_cast<double>(kept.size()) / target;
    const double error = std::abs(ratio - 1.0);
    if (error < best_error) {
      best_error = error;
      out.samples = std::move(kept);
      out.radius = radius;
      out.root_depth = depth;
    }
    if (error < 0.02) break;
    // the count goes about as r^-2.5 in a layer of hair a few samples thick
    radius *= static_cast<float>(std::pow(ratio, 1.0 / 2.5));
  }
  return out;
}

}  // namespace loosehair
