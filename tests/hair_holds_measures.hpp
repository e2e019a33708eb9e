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

// Per render strand, how far it comes back towards the bodies after
// leaving them above `centre_y` (the crown): the largest drop of its
// distance from the bodies from one point to a later one, both above
// centre_y (m). Hair lying on the head only moves away from it.
inline std::vector<float> crownLoops(const loosehair::StrandSet& rest, const std::vector<glm::vec3>& points,
                                     const loosehair::BodyContacts& bodies, float centre_y) {
  std::vector<float> phi(points.size());
  std::vector<glm::vec3> normal(points.size());
  bodies(points, INFINITY, false, phi, normal);
  std::vector<float> loop(rest.size(), 0.0f);
  for (std::size_t k = 0; k < rest.size(); ++k) {
    float highest = -INFINITY;
    for (std::uint32_t q = rest.first[k]; q < rest.first[k + 1]; ++q) {
      if (points[q].y < centre_y) continue;
      highest = std::max(highest, phi[q]);
      loop[k] = std::max(loop[k], highest - phi[q]);
    }
  }
  return loop;
}

inline std::size_t fasterThan(const loosehair::Particles& p, float speed) {
  std::size_t fast = 0;
  for (std::size_t i = 0; i < p.size(); ++i) fast += !p.is_root[i] && glm::length(p.velocity[i]) > speed;
  return fast;
}

}  // namespace lhtest
