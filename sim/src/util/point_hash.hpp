// Points hashed into cubic cells of one size, for "is any point nearer than
// r?" with r at most the cell size (Poisson-disc darts, scalp coverage).
#pragma once

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace loosehair {

class PointHash {
 public:
  /// `cell` (m, > 0): the largest radius anyNearer may be asked.
  explicit PointHash(float cell) : cell_(cell) {}
  void add(glm::vec3 p) { cells_[key(cellOf(p))].push_back(p); }
  /// Whether a point added lies nearer than `radius` (<= the cell) to p.
  bool anyNearer(glm::vec3 p, float radius) const {
    const glm::ivec3 c = cellOf(p);
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const auto it = cells_.find(key(c + glm::ivec3(dx, dy, dz)));
          if (it == cells_.end()) continue;
          for (const glm::vec3& q : it->second)
            if (glm::length(q - p) < radius) return true;
        }
    return false;
  }

 private:
  glm::ivec3 cellOf(glm::vec3 p) const { return glm::ivec3(glm::floor(p / cell_)); }
  static std::int64_t key(glm::ivec3 c) {
    return (static_cast<std::int64_t>(c.x) * 73856093) ^ (static_cast<std::int64_t>(c.y) * 19349663) ^
           (static_cast<std::int64_t>(c.z) * 83492791);
  }
  float cell_;
  std::unordered_map<std::int64_t, std::vector<glm::vec3>> cells_;
};

}  // namespace loosehair
