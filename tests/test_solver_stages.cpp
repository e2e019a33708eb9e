// Stages of the step alone, on hand-made particles (no scene, no solver):
// the strain limit (solver/strain_limit.hpp), the tethers
// (solver/tethers.hpp) and the direction pass (solver/directions.hpp).
#include "connection_builder.hpp"
#include "solver/connection_passes.hpp"
#include "solver/directions.hpp"
#include "solver/strain_limit.hpp"
#include "solver/tethers.hpp"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

using namespace loosehair;

namespace {

// A hair hanging straight down from a root at the origin: n particles l
// apart, the first a root, all pointing down.
struct Hair {
  std::vector<glm::vec3> x, t;
  std::vector<float> s, mass;
  std::vector<std::uint8_t> root;
  ConnectionSet c;
  SlicedConnections sliced;
  Hair(int n, float l, float h1) {
    for (int i = 0; i < n; ++i) {
      x.push_back({0.0f, -l * static_cast<float>(i), 0.0f});
      t.push_back({0.0f, -1.0f, 0.0f});
      s.push_back(l * static_cast<float>(i));
      mass.push_back(1e-4f);
      root.push_back(i == 0 ? 1 : 0);
    }
    ConnectionOptions o;
    o.h1 = h1;
    c = buildConnections(x, t, s, root, o);
    sliced = sliceForPasses(c);
  }
  // (x, 1/m) records of positions p, as integrate makes them
  std::vector<glm::vec4> records(const std::vector<glm::vec3>& p) const {
    std::vector<glm::vec4> r;
    for (std::size_t i = 0; i < p.size(); ++i) r.emplace_back(p[i], root[i] ? 0.0f : 1.0f / mass[i]);
    return r;
  }
  std::size_t limit(std::vector<glm::vec3>& p, int rounds, int threads = 1) const {
    std::vector<glm::vec4> rec[2] = {records(p), {}};
    std::vector<glm::vec3> scratch;
    return limitStrain({0.012f, 0.01f, rounds}, sliced, root, p, rec, scratch, threads);
  }
};

}  // namespace

TEST(StrainLimitStage, PullsAnOverStretchedHairBackAndNeverMovesTheRoot) {
  const Hair h(2, 0.01f, 0.012f);
  ASSERT_EQ(h.c.pairCount(), 1u);
  std::vector<glm::vec3> p = h.x;
  p[1].y = -0.015f;  // 50 % over its rest length, within the support 2 h1
  EXPECT_EQ(h.limit(p, 1), 1u);
  EXPECT_EQ(p[0], h.x[0]) << "a root does not move";
  // one round moves it back by the excess over (1 + 1 %) l, scaled by how
  // loose the spring is there (W(r) / W(l) < 1): part of the way
  const float after_one = glm::length(p[1] - p[0]);
  EXPECT_LT(after_one, 0.015f);
  EXPECT_GT(after_one, 0.0101f);
  EXPECT_FLOAT_EQ(p[1].x, 0.0f);
  EXPECT_FLOAT_EQ(p[1].z, 0.0f);
  // more rounds come nearer the limit, never past it
  std::vector<glm::vec3> q = h.x;
  q[1].y = -0.015f;
  h.limit(q, 20);
  const float after_many = glm::length(q[1] - q[0]);
  EXPECT_LT(after_many, after_one);
  EXPECT_GE(after_many, 0.0101f * (1.0f - 1e-5f));
}

TEST(StrainLimitStage, LeavesSlackAndReleasedConnectionsAlone) {
  const Hair h(2, 0.01f, 0.012f);
  std::vector<glm::vec3> slack = h.x;
  slack[1].y = -0.008f;  // shorter than rest
  EXPECT_EQ(h.limit(slack, 4), 0u);
  EXPECT_EQ(slack[1], glm::vec3(0.0f, -0.008f, 0.0f));
  std::vector<glm::vec3> gone = h.x;
  gone[1].y = -0.03f;  // beyond the support 2 h1: the hair let go here
  EXPECT_EQ(h.limit(gone, 4), 0u);
  EXPECT_EQ(gone[1], glm::vec3(0.0f, -0.03f, 0.0f));
}

TEST(StrainLimitStage, MovesTwoEqualParticlesEquallyAndKeepsTheirCentre) {
  const Hair h(3, 0.01f, 0.012f);
  std::vector<glm::vec3> p = h.x;
  // root, then 1 and 2 pulled apart symmetrically about their centre
  p[1].y = -0.010f;
  p[2].y = -0.024f;
  const glm::vec3 centre = 0.5f * (p[1] + p[2]);
  // only the 1-2 connection is over-stretched if 1 stays at rest from the root
  h.limit(p, 1);
  EXPECT_LT(glm::length(p[2] - p[1]), 0.014f);
  // 1 is pulled by the root's connection too (it is at rest: no pull), and
  // by 2; 2 by 1 only: equal inverse masses share the excess equally
  EXPECT_NEAR(0.5f * (p[1].y + p[2].y), centre.y, 1e-7f);
}

TEST(StrainLimitStage, GivesTheSameBitsOnAnyThreadCount) {
  // a long hair, jittered and stretched
  const Hair h(2000, 0.004f, 0.0048f);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> jitter(-0.001f, 0.001f);
  std::vector<glm::vec3> p = h.x;
  for (std::size_t i = 1; i < p.size(); ++i) p[i] = 1.01f * p[i] + glm::vec3(jitter(rng), jitter(rng), jitter(rng));
  std::vector<glm::vec3> one = p, two = p;
  const std::size_t a = h.limit(one, 4, 1), b = h.limit(two, 4, 2);
  EXPECT_GT(a, 100u);
  EXPECT_EQ(a, b);
  EXPECT_EQ(std::memcmp(one.data(), two.data(), one.size() * sizeof(glm::vec3)), 0);
}

TEST(TetherStage, HoldsEachParticleWithinReachOfItsRootAndTie) {
  const std::vector<std::uint8_t> root = {1, 0, 0, 0};
  const std::vector<glm::vec3> rp(4, glm::vec3(0.0f));
  const std::vector<float> s = {0.0f, 0.1f, 0.2f, 0.2f};
  std::vector<glm::vec3> x = {{0.0f, 0.3f, 0.0f}, {0.0f, -0.05f, 0.0f}, {0.3f, -0.4f, 0.0f}, {0.0f, -0.2f, 0.0f}};
  applyTethers(0.01f, root, rp, s, {}, {}, x, 2);
  EXPECT_EQ(x[0], glm::vec3(0.0f, 0.3f, 0.0f)) << "a root is not tethered";
  EXPECT_EQ(x[1], glm::vec3(0.0f, -0.05f, 0.0f)) << "within reach: not moved";
  EXPECT_NEAR(glm::length(x[2]), 1.01f * 0.2f, 1e-6f) << "beyond reach: onto it";
  EXPECT_NEAR(x[2].x / x[2].y, 0.3f / -0.4f, 1e-6f) << "along the line to the root";
  EXPECT_EQ(x[3], glm::vec3(0.0f, -0.2f, 0.0f));
  // a tie 5 cm to the side with a reach of 1 cm pulls particle 3 to it
  const std::vector<glm::vec3> tie(4, glm::vec3(0.05f, -0.2f, 0.0f));
  const std::vector<float> reach = {-1.0f, -1.0f, -1.0f, 0.01f};
  applyTethers(0.0f, root, rp, s, tie, reach, x, 1);
  EXPECT_NEAR(glm::length(x[3] - tie[3]), 0.01f, 1e-6f) << "the tie comes last: it holds";
  EXPECT_NEAR(x[3].y, -0.2f, 1e-7f);
}

// The direction pass (solver/directions.hpp) on the same straight hair.
TEST(DirectionStage, TurnsAStrayDirectionBackAlongTheHairAndMeasuresTheNextSprings) {
  const Hair h(5, 0.01f, 0.012f);
  const std::size_t n = h.x.size();
  std::vector<glm::vec3> dir = h.t;
  dir[2] = glm::normalize(glm::vec3(1.0f, -0.2f, 0.0f));  // knocked sideways
  dir[0] = glm::vec3(1.0f, 0.0f, 0.0f);                   // a root keeps whatever it has
  const std::vector<glm::vec3> v(n, glm::vec3(0.0f));
  std::vector<float> weight(h.sliced.layout.entryCount(), 1.0f);
  std::vector<float> sum_root(n, -1.0f), sum_tip(n, -1.0f);
  const DirectionPassResult r =
      updateDirections(0.012f, h.sliced, weight, h.root, h.x, v, dir, sum_root, sum_tip, 2);
  EXPECT_EQ(r.broken, 0u);
  EXPECT_EQ(r.active_entries, 2 * h.c.pairCount());
  EXPECT_NEAR(dir[2].x, 0.0f, 1e-6f);
  EXPECT_NEAR(dir[2].y, -1.0f, 1e-6f);
  EXPECT_EQ(dir[0], glm::vec3(1.0f, 0.0f, 0.0f));
  // the side sums of l_ij k_ij at these (rest) positions: what the factor
  // pass of the next step divides E A by
  for (std::size_t i = 0; i < n; ++i) {
    double root_side = 0, tip_side = 0;
    const CubicKernel k1(0.012f);
    for (std::uint32_t e = h.c.begin(i); e < h.c.end(i); ++e) {
      const float l = h.c.rest_length[e];
      (h.c.tip_side[e] ? tip_side : root_side) += static_cast<double>(l) * h.c.strength[e] * k1.W(l);
    }
    EXPECT_NEAR(sum_root[i], root_side, 1e-6 * root_side + 1e-12) << i;
    EXPECT_NEAR(sum_tip[i], tip_side, 1e-6 * tip_side + 1e-12) << i;
  }
  // no active connection (all weights 0): a particle keeps its direction
  std::vector<float> none(weight.size(), 0.0f);
  std::vector<glm::vec3> kept = dir;
  kept[3] = glm::vec3(0.0f, 0.0f, 1.0f);
  updateDirections(0.012f, h.sliced, none, h.root, h.x, v, kept, sum_root, sum_tip, 1);
  EXPECT_EQ(kept[3], glm::vec3(0.0f, 0.0f, 1.0f));
  // a state that is not finite is counted, never passed on silently
  std::vector<glm::vec3> bad_v = v;
  bad_v[4].y = NAN;
  EXPECT_EQ(updateDirections(0.012f, h.sliced, weight, h.root, h.x, bad_v, dir, sum_root, sum_tip, 1).broken, 1u);
}
