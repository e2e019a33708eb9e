// The hair chain: each hair particle stays within reach of hair nearer its
// root in its own root region (our addition to the LCP connections, with
// the tethers). The loose springs of the paper let go of a partner beyond
// their support 2 h1, and so does the strain limit; under a fast turn or
// nod a clump flung beyond the support of all its partners was held by
// its tethers alone and lay on the shoulders or floated off (issue 43).
//
// "Nearer the root" is a smaller arc length s; a particle's candidates are
// its partners nearer the root. A particle none of whose candidates is
// within reach (kSupportFraction of the support 2 h1, or the pair's rest
// length where that is longer), and no held particle nearer the root of
// its root region within the support reach either, moves towards
// whichever needs the shorter move, the nearest candidate or the nearest
// such hair, until it is within reach. Hanging hair settles far from its
// first partners (constraining it to them held it 7 cm higher), but never
// far from the hair of its region nearer the root. Particles are visited
// by arc length, so everything nearer the root has been placed first: a
// loose clump is drawn back from its root end on, cannot hold itself up,
// and one pass meets every particle's reach. docs/design.md, "The hair
// chain", has the choices and what each fixed.
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
  /// Other hair holds a particle only if rooted in its root region, within
  /// this many support reaches of its root (or as far as its candidates):
  /// hair of another part of the scalp does not (a particle held by any
  /// hair wandered 12 cm from the hair of its own part of the scalp in a
  /// turn and a nod).
  static constexpr float kRegionReaches = 2.0f;

  HairChain() = default;
  HairChain(const ConnectionSet& connections, std::span<const std::uint8_t> is_root, std::span<const float> arc_length,
            std::span<const glm::vec3> root_point, float h1);

  /// Moves each linked particle (by arc length) that has no particle of its
  /// root region nearer its root (smaller arc length `s`) within the reach
  /// of the support, and none of its candidates within reach either, to
  /// within reach of the nearest candidate or region's hair (the shorter
  /// move), then back within its tethers (`tether(i, x_i)`
  /// returns x_i tethered), alternating twice so that both hold where both
  /// can; returns how many moved.
  template <class Tether>
  std::size_t project(std::span<glm::vec3> x, std::span<const float> s, const Tether& tether) const {
    std::size_t moved = 0;
    bool grid_made = false;
    for (std::uint32_t i : order_) {
      const glm::vec3 before = x[i];
      // the nearest candidate, in units of its reach
      float best = INFINITY;
      std::uint32_t at = first_[i];
      for (std::uint32_t k = first_[i]; k < first_[i + 1]; ++k) {
        const glm::vec3 d = before - x[candidate_[k]];
        const float r = glm::dot(d, d) / (reach_[k] * reach_[k]);
        if (r < best) best = r, at = k;
      }
      if (best <= 1.0f) continue;
      // any hair nearer the root close by holds it as well (the hair has
      // settled away from its first partners, as hanging hair does)
      if (!grid_made) {
        makeGrid(x);
        grid_made = true;
      }
      if (nearerHairWithin(x, s, i)) continue;
      // towards whichever needs the shorter move: the nearest candidate, or
      // the nearest other hair nearer the root (within two reaches), so
      // that hair that fell past the hair nearer its root rests at its
      // edge rather than being drawn back up to its first partners, to
      // fall again
      glm::vec3 p = x[candidate_[at]];
      float reach = reach_[at];
      const float move = std::sqrt(best) * reach - reach;
      std::uint32_t near = i;
      if (nearestNearerHair(x, s, i, near) && glm::distance(x[near], before) - support_reach_ < move) {
        p = x[near];
        reach = support_reach_;
      }
      glm::vec3 xi = before;
      for (int pass = 0; pass < 2; ++pass) xi = tether(i, within(xi, p, reach));
      if (xi != before) {
        x[i] = xi;
        ++moved;
      }
    }
    return moved;
  }

  /// Whether j's root is in i's root region: within kRegionReaches support
  /// reaches of i's root, or as far as i's farthest-rooted candidate.
  bool inRegion(std::size_t i, std::size_t j) const {
    return sameRegion(static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j));
  }

  /// Particles with candidates.
  std::size_t linked() const { return order_.size(); }
  /// The candidates of particle i (none for a root, or for a particle with
  /// no partner nearer the root) and their reaches (m).
  std::span<const std::uint32_t> candidates(std::size_t i) const {
    return {candidate_.data() + first_[i], first_[i + 1] - first_[i]};
  }
  std::span<const float> reaches(std::size_t i) const { return {reach_.data() + first_[i], first_[i + 1] - first_[i]}; }

 private:
  static glm::vec3 within(const glm::vec3& x, const glm::vec3& p, float reach) {
    const glm::vec3 d = x - p;
    const float r2 = glm::dot(d, d);
    return r2 > reach * reach ? p + (reach / std::sqrt(r2)) * d : x;
  }
  void makeGrid(std::span<const glm::vec3> x) const;
  /// Calls visit(j, |x_j - x_i|^2) for each holder j nearer the root of i's
  /// root region in the grid cells within `cells` of i's, until it returns
  /// true.
  template <class Visit>
  void forEachHolder(std::span<const glm::vec3> x, std::span<const float> s, std::uint32_t i, int cells,
                     const Visit& visit) const;
  bool nearerHairWithin(std::span<const glm::vec3> x, std::span<const float> s, std::uint32_t i) const;
  /// The nearest particle that holds (a root or linked) nearer the root
  /// than i within two support reaches of it, in `nearest`; false if none.
  bool nearestNearerHair(std::span<const glm::vec3> x, std::span<const float> s, std::uint32_t i,
                         std::uint32_t& nearest) const;
  bool sameRegion(std::uint32_t i, std::uint32_t j) const {
    const glm::vec3 d = root_[j] - root_[i];
    return glm::dot(d, d) <= region2_[i];
  }
  float support_reach_ = 0.0f;            // kSupportFraction * 2 h1
  std::vector<float> region2_;            // the root region's radius^2 (m^2)
  std::vector<glm::vec3> root_;           // each particle's root point
  std::vector<std::uint32_t> order_;      // linked particles by arc length
  std::vector<std::uint32_t> first_;      // candidates of i: [first_[i], first_[i + 1])
  std::vector<std::uint32_t> candidate_;  // partners nearer the root
  std::vector<float> reach_;              // per candidate (m)
  std::vector<std::uint8_t> holds_;       // a root or a linked particle
  // the particles sorted by grid cell (cells of support_reach_), made when
  // a pass first needs it
  mutable std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed_;  // makeGrid's scratch
  mutable std::vector<std::uint64_t> cell_key_;
  mutable std::vector<std::uint32_t> cell_particle_;
};

}  // namespace loosehair
