// The hair chain (sim/src/hair_chain.hpp): every hair particle has a parent,
// a root-side partner nearer a root, and is kept within the springs'
// support of it, so that no particle or clump comes loose from the hair.
#include "test_support.hpp"

#include "hair_chain.hpp"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

using namespace loosehair;

TEST(HairChain, ParentsLeadToARootAndAreRootSidePartners) {
  Solver s = buildSolver(lhtest::sphereScene(1500));
  const Particles& p = s.particles();
  const ConnectionSet& c = s.connections();
  std::size_t linked = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.is_root[i]) {
      EXPECT_EQ(s.chainParent(i), UINT32_MAX);
      continue;
    }
    const std::uint32_t parent = s.chainParent(i);
    if (parent == UINT32_MAX) continue;  // (unanchored: reported by the build)
    ++linked;
    // a root-side partner of i
    bool partner = false;
    for (std::uint32_t e = c.begin(i); e < c.tipBegin(i); ++e) partner = partner || c.partner[e] == parent;
    EXPECT_TRUE(partner) << "particle " << i;
    EXPECT_LE(s.chainReach(i), 2.0f * s.params().h1 + 1e-6f);
    // following parents reaches a root, without a cycle
    std::size_t at = i, steps = 0;
    while (!p.is_root[at] && steps <= p.size()) at = s.chainParent(at), ++steps;
    EXPECT_TRUE(p.is_root[at]) << "particle " << i;
  }
  EXPECT_EQ(linked + s.initReport().roots + s.initReport().unanchored, p.size());
}

TEST(HairChain, AFlungParticleIsBroughtBackWithinReachOfItsParent) {
  // the projection itself: a particle thrown a metre away comes back to the
  // sphere of its parent's reach, its children after it
  Solver s = buildSolver(lhtest::sphereScene(800));
  const Particles& p = s.particles();
  HairChain chain(s.connections(), p.is_root, s.params().h1);
  std::vector<glm::vec3> x = p.position;
  std::size_t victim = 0;
  for (std::size_t i = 0; i < x.size(); ++i)
    if (!p.is_root[i] && chain.parent(i) != UINT32_MAX && p.arc_length[i] > p.arc_length[victim]) victim = i;
  x[victim] += glm::vec3(1.0f, 0.0f, 0.0f);
  const std::size_t moved = chain.project(std::span<glm::vec3>(x), [](std::size_t, glm::vec3 y) { return y; });
  EXPECT_GE(moved, 1u);
  for (std::size_t i = 0; i < x.size(); ++i)
    if (chain.parent(i) != UINT32_MAX)
      EXPECT_LE(glm::length(x[i] - x[chain.parent(i)]), chain.reach(i) * 1.0001f) << "particle " << i;
  // untouched particles stay where they were
  EXPECT_EQ(x[0], p.position[0]);
}
