// The hair chain: each hair particle keeps one root-side partner, its
// parent, within reach (our addition to the LCP connections, with the
// tethers). The loose springs of the paper let go of a partner beyond the
// kernel's support h1, and so does the strain limit; under a fast turn or
// nod a clump flung beyond h1 of all its partners was held by its tethers
// alone and lay on the shoulders or floated off (issue 43). The chain keeps
// every particle within reach of a particle nearer its root, which is
// within reach of one nearer still, down to a root: hair splits sideways
// between chains as before, but no particle or clump comes loose.
//
// The parents form a forest over the root-side connections: found by a
// breadth-first walk from the roots along tip-side connections, each
// particle's parent is its nearest (at rest) root-side partner of a lower
// depth. A link reaches kSupportFraction of the springs' support 2 h1 (or
// its rest length where that is longer): the pair's spring and strain limit
// never let go, and the link itself acts only where they would have.
// Projecting in that order (follow the leader: only the child moves)
// meets every link in one pass.
#pragma once

#include "loosehair/connections.hpp"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

namespace loosehair {

class HairChain {
 public:
  static constexpr float kSupportFraction = 0.95f;

  HairChain() = default;
  HairChain(const ConnectionSet& connections, std::span<const std::uint8_t> is_root, float h1);

  /// Moves each linked particle (parents first) to within reach of its
  /// parent, along the line to it, and back within its tethers
  /// (`tether(i, x_i)` returns x_i tethered), alternating twice so that
  /// both hold where both can; returns how many moved.
  template <class Tether>
  std::size_t project(std::span<glm::vec3> x, const Tether& tether) const {
    std::size_t moved = 0;
    for (std::uint32_t i : order_) {
      const glm::vec3 p = x[parent_[i]], before = x[i];
      glm::vec3 xi = before;
      for (int pass = 0; pass < 2; ++pass) xi = tether(i, within(xi, p, reach_[i]));
      if (xi != before) {
        x[i] = xi;
        ++moved;
      }
    }
    return moved;
  }

  /// Particles with a parent.
  std::size_t linked() const { return order_.size(); }
  /// The parent of particle i (UINT32_MAX for a root or a particle that
  /// reaches no root through root-side connections).
  std::uint32_t parent(std::size_t i) const { return parent_[i]; }
  float reach(std::size_t i) const { return reach_[i]; }

 private:
  static glm::vec3 within(const glm::vec3& x, const glm::vec3& p, float reach) {
    const glm::vec3 d = x - p;
    const float r2 = glm::dot(d, d);
    return r2 > reach * reach ? p + (reach / std::sqrt(r2)) * d : x;
  }
  std::vector<std::uint32_t> order_;   // linked particles, parents before children
  std::vector<std::uint32_t> parent_;  // per particle
  std::vector<float> reach_;           // per particle (m)
};

}  // namespace loosehair
