// The hair chain (sim/src/solver/hair_chain.hpp): every hair particle stays within
// reach of a root-side partner nearer a root, so that no particle or clump
// comes loose from the hair.
#include "test_support.hpp"

#include "solver/hair_chain.hpp"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

using namespace loosehair;

namespace {

// Following candidates from i reaches a root (each is nearer one).
bool leadsToARoot(const HairChain& chain, const Particles& p, std::size_t i) {
  std::size_t at = i, steps = 0;
  while (!p.is_root[at] && !chain.candidates(at).empty() && steps++ <= p.size()) at = chain.candidates(at)[0];
  return p.is_root[at];
}

}  // namespace

TEST(HairChain, CandidatesArePartnersNearerTheRootLeadingToARoot) {
  Solver s = buildSolver(lhtest::sphereScene(1500, R"({"hair_chain": true})"));
  const Particles& p = s.particles();
  const ConnectionSet& c = s.connections();
  HairChain chain(c, p.is_root, p.arc_length, p.root_point, s.params().h1);
  std::size_t linked = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const auto cand = chain.candidates(i);
    if (p.is_root[i]) {
      EXPECT_TRUE(cand.empty());
      continue;
    }
    if (cand.empty()) continue;  // (unanchored: reported by the build)
    ++linked;
    for (std::uint32_t j : cand) {
      bool partner = false;
      for (std::uint32_t e = c.begin(i); e < c.end(i); ++e) partner = partner || c.partner[e] == j;
      EXPECT_TRUE(partner) << "particle " << i << ", candidate " << j;
      EXPECT_LT(p.arc_length[j], p.arc_length[i]);
    }
    for (float r : chain.reaches(i)) EXPECT_LE(r, 2.0f * s.params().h1 + 1e-6f);
    EXPECT_TRUE(leadsToARoot(chain, p, i)) << "particle " << i;
    // at rest every particle is within reach
    EXPECT_LE(s.chainGap(i), 1.0f + 1e-5f) << "particle " << i;
  }
  EXPECT_EQ(linked, chain.linked());
  EXPECT_GE(linked + s.initReport().roots + s.initReport().unanchored, p.size());
}

TEST(HairChain, AFlungClumpIsBroughtBackWithinReachAndTheRestIsLeftAlone) {
  Solver s = buildSolver(lhtest::sphereScene(800));
  const Particles& p = s.particles();
  HairChain chain(s.connections(), p.is_root, p.arc_length, p.root_point, s.params().h1);
  // the outer half of the hair thrown a metre away, as a clump
  std::vector<glm::vec3> x = p.position;
  float longest = 0.0f;
  for (float a : p.arc_length) longest = std::max(longest, a);
  for (std::size_t i = 0; i < x.size(); ++i)
    if (p.arc_length[i] > 0.5f * longest) x[i] += glm::vec3(1.0f, 0.0f, 0.0f);
  const std::size_t moved =
      chain.project(std::span<glm::vec3>(x), p.arc_length, [](std::size_t, glm::vec3 y) { return y; });
  EXPECT_GT(moved, 0u);
  // every thrown particle is drawn back until it is within reach of a
  // candidate or of other hair nearer the root (the chain may stay drawn
  // out, link by link, as far as the tethers let it: none here), and the
  // rest is left alone
  const float support_reach = HairChain::kSupportFraction * 2.0f * s.params().h1;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (p.arc_length[i] <= 0.5f * longest) {
      EXPECT_EQ(x[i], p.position[i]) << "particle " << i << " moved";
      continue;
    }
    const auto cand = chain.candidates(i);
    if (cand.empty()) continue;
    bool held = false;
    for (std::size_t k = 0; k < cand.size(); ++k)
      held = held || glm::length(x[i] - x[cand[k]]) <= chain.reaches(i)[k] * 1.0001f;
    for (std::size_t j = 0; j < x.size() && !held; ++j)
      held = p.arc_length[j] < p.arc_length[i] && !chain.candidates(j).empty() &&
             glm::length(x[i] - x[j]) < support_reach * 1.0001f;
    EXPECT_TRUE(held) << "particle " << i << " was left loose";
  }
}
