// Measures of hair that holds together (issue 43), shared by the scenario
// tests of the bundled head and of heads like users bring: loose particles,
// distance to the hair of the same root region, render strands that loop
// away from the crown, particles still moving.
#pragma once

#include "loosehair/particles.hpp"
#include "loosehair/strand_field.hpp"
#include "loosehair/style.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace lhtest {

// The particles not joined to any root through particles closer than
// `radius` to each other (a breadth-first walk from the roots).
inline std::size_t looseParticles(const std::vector<glm::vec3>& x, const std::vector<std::uint8_t>& root,
                                  float radius) {
  const std::size_t n = x.size();
  std::vector<std::uint8_t> reached(n, 0);
  std::vector<std::uint32_t> queue;
  for (std::uint32_t i = 0; i < n; ++i)
    if (root[i]) reached[i] = 1, queue.push_back(i);
  // brute force on a few thousand particles: n^2 / 2 distance checks at most
  for (std::size_t q = 0; q < queue.size(); ++q) {
    const glm::vec3 a = x[queue[q]];
    for (std::uint32_t j = 0; j < n; ++j)
      if (!reached[j] && glm::dot(x[j] - a, x[j] - a) < radius * radius) reached[j] = 1, queue.push_back(j);
  }
  return n - queue.size();
}

// The largest distance from a hair particle to the nearest other particle
// of its root region (`same(i, j)`: j is rooted in i's region) (m).
template <class Same>
float farthestFromItsRegion(const loosehair::Particles& p, const Same& same) {
  float worst = 0.0f;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.is_root[i]) continue;
    float nearest = INFINITY;
    for (std::size_t j = 0; j < p.size(); ++j)
      if (j != i && same(i, j)) nearest = std::min(nearest, glm::distance(p.position[j], p.position[i]));
    worst = std::max(worst, nearest);
  }
  return worst;
}

// Per render strand, how far it turns back towards its root over the
// crown: the largest drop of a point's distance from the strand's root
// below the largest before it, over the points above `centre_y` (m). A
// strand that hangs or lies on the head only gets farther from its root;
// one that loops comes back. (Distance from the head is no measure: a
// strand lying on the hair can end on the bare forehead.)
inline std::vector<float> crownLoops(const loosehair::StrandSet& rest, const std::vector<glm::vec3>& points,
                                     float centre_y) {
  std::vector<float> loop(rest.size(), 0.0f);
  for (std::size_t k = 0; k < rest.size(); ++k) {
    const glm::vec3 root = points[rest.first[k]];
    float farthest = 0.0f;
    for (std::uint32_t q = rest.first[k]; q < rest.first[k + 1]; ++q) {
      if (points[q].y < centre_y) continue;
      const float r = glm::distance(points[q], root);
      farthest = std::max(farthest, r);
      loop[k] = std::max(loop[k], farthest - r);
    }
  }
  return loop;
}

inline float fastest(const loosehair::Particles& p) {
  float most = 0.0f;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (!p.is_root[i]) most = std::max(most, glm::length(p.velocity[i]));
  return most;
}

inline std::size_t fasterThan(const loosehair::Particles& p, float speed) {
  std::size_t fast = 0;
  for (std::size_t i = 0; i < p.size(); ++i) fast += !p.is_root[i] && glm::length(p.velocity[i]) > speed;
  return fast;
}

}  // namespace lhtest
