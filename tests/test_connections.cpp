// SPEC §3.1: alignment, thresholds, pruning and the connectivity check.
#include "connection_builder.hpp"
#include "random.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace loosehair;

TEST(Alignment, HandMadeConfigurations) {
  const glm::vec3 down(0, -1, 0);
  // j below i along the hair, both pointing down: fully aligned
  EXPECT_FLOAT_EQ(alignment(down, down, glm::vec3(0, -0.01f, 0)), 1.0f);
  // the same seen from j
  EXPECT_FLOAT_EQ(alignment(down, down, glm::vec3(0, 0.01f, 0)), 1.0f);
  // side by side across the hair: zero
  EXPECT_FLOAT_EQ(alignment(down, down, glm::vec3(0.01f, 0, 0)), 0.0f);
  // opposite directions: cos(theta_ij) cos(theta_ji) > 0, so zero
  EXPECT_FLOAT_EQ(alignment(down, -down, glm::vec3(0, -0.01f, 0)), 0.0f);
  // 45 degrees off the hair: (cos 45 + cos 45) / 2
  EXPECT_NEAR(alignment(down, down, glm::vec3(0.01f, -0.01f, 0)), std::sqrt(0.5f), 1e-6f);
  // one hair tilted: |cos a + cos b| / 2
  const glm::vec3 tilted = glm::normalize(glm::vec3(1, -1, 0));
  EXPECT_NEAR(alignment(down, tilted, glm::vec3(0, -0.01f, 0)), (1.0f + std::sqrt(0.5f)) / 2,
              1e-6f);
  // degenerate pair vector
  EXPECT_EQ(alignment(down, down, glm::vec3(0)), 0.0f);
}

namespace {

struct Block {
  std::vector<glm::vec3> x, t;
  std::vector<float> s;
  std::vector<std::uint8_t> root;
};

// Jittered strands hanging down from a root layer.
Block hairBlock(std::uint64_t seed) {
  Random rng(seed);
  Block b;
  const float a = 0.01f;
  for (int i = 0; i < 10; ++i)
    for (int k = 0; k < 10; ++k)
      for (int j = -1; j < 20; ++j) {
        b.x.emplace_back(i * a + rng.uniform(-0.2, 0.2) * a, -j * a + rng.uniform(-0.2, 0.2) * a,
                         k * a + rng.uniform(-0.2, 0.2) * a);
        b.t.push_back(glm::normalize(glm::vec3(rng.uniform(-0.1, 0.1), -1, rng.uniform(-0.1, 0.1))));
        b.s.push_back(j * a);
        b.root.push_back(j < 0 ? 1 : 0);
      }
  return b;
}

}  // namespace

TEST(Connections, ThresholdSidesAndSymmetry) {
  const Block b = hairBlock(5);
  ConnectionOptions opt;
  opt.h1 = 0.012f;
  opt.target_connections = 12;
  const ConnectionSet c = buildConnections(b.x, b.t, b.s, b.root, opt);
  ASSERT_EQ(c.particleCount(), b.x.size());
  for (std::size_t i = 0; i < b.x.size(); ++i) {
    ASSERT_LE(c.begin(i), c.tipBegin(i));
    ASSERT_LE(c.tipBegin(i), c.end(i));
    for (std::uint32_t e = c.begin(i); e < c.end(i); ++e) {
      const std::uint32_t j = c.partner[e];
      EXPECT_FALSE(b.root[i] && b.root[j]) << "root-root connection";
      EXPECT_LT(c.rest_length[e], 2 * opt.h1);
      // the pair is stored on both sides with opposite side flags
      bool found = false;
      for (std::uint32_t f = c.begin(j); f < c.end(j); ++f)
        if (c.partner[f] == i) {
          found = true;
          EXPECT_EQ(c.rest_length[f], c.rest_length[e]);
          EXPECT_EQ(c.strength[f], c.strength[e]);
          EXPECT_NE(c.tip_side[f], c.tip_side[e]);
        }
      EXPECT_TRUE(found);
      // root side first, then tip side (the solver's loops rely on it)
      EXPECT_EQ(c.tip_side[e] != 0, e >= c.tipBegin(i));
      // tip side means further along the hair
      if (b.s[j] != b.s[i]) {
        EXPECT_EQ(c.tip_side[e] != 0, b.s[j] > b.s[i]);
      }
      const float a = alignment(b.t[i], b.t[j], b.x[j] - b.x[i]);
      EXPECT_NEAR(c.strength[e], a * c.rest_length[e], 1e-6f);
    }
  }
  EXPECT_EQ(countUnanchored(c, b.root), 0u);
}

TEST(Connections, PruningKeepsDegreesNearTargetAndIsDeterministic) {
  const Block b = hairBlock(6);
  for (int nn : {6, 12}) {
    ConnectionOptions opt;
    opt.h1 = 0.016f;  // many candidates
    opt.target_connections = nn;
    opt.threads = 1;
    const ConnectionSet one = buildConnections(b.x, b.t, b.s, b.root, opt);
    opt.threads = 2;
    const ConnectionSet two = buildConnections(b.x, b.t, b.s, b.root, opt);
    EXPECT_EQ(one.partner, two.partner);
    EXPECT_EQ(one.rest_length, two.rest_length);

    opt.target_connections = 1000;  // no pruning
    const ConnectionSet all = buildConnections(b.x, b.t, b.s, b.root, opt);
    double sum = 0;
    std::size_t count = 0;
    for (std::size_t i = 0; i < b.x.size(); ++i) {
      if (b.root[i]) continue;
      sum += one.degree(i);
      ++count;
      EXPECT_LE(one.degree(i), all.degree(i));
      // pruning never removes the last root-side or tip-side partner
      auto has = [&](const ConnectionSet& c, std::uint8_t tip) {
        for (std::uint32_t e = c.begin(i); e < c.end(i); ++e)
          if (c.tip_side[e] == tip) return true;
        return false;
      };
      if (has(all, 0)) {
        EXPECT_TRUE(has(one, 0)) << "particle " << i;
      }
      if (has(all, 1)) {
        EXPECT_TRUE(has(one, 1)) << "particle " << i;
      }
    }
    const double mean = sum / static_cast<double>(count);
    EXPECT_GT(all.pairCount(), one.pairCount());
    EXPECT_GE(mean, 0.9 * nn) << "Nn = " << nn;
    EXPECT_LE(mean, 1.4 * nn) << "Nn = " << nn;
    EXPECT_EQ(countUnanchored(one, b.root), 0u);
  }
}

TEST(Connections, UnanchoredParticlesAreCounted) {
  Block b = hairBlock(7);
  // a lonely particle far away from everything
  b.x.emplace_back(5.0f, 5.0f, 5.0f);
  b.t.emplace_back(0, -1, 0);
  b.s.push_back(0.05f);
  b.root.push_back(0);
  ConnectionOptions opt;
  opt.h1 = 0.012f;
  const ConnectionSet c = buildConnections(b.x, b.t, b.s, b.root, opt);
  EXPECT_EQ(countUnanchored(c, b.root), 1u);
}

TEST(Connections, BundledSceneIsFullyAnchored) {
  auto scene = lhtest::sphereScene(1500);
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    scene.seed = seed;
    const Solver solver = buildSolver(scene);
    EXPECT_EQ(solver.initReport().unanchored, 0u) << "seed " << seed;
    EXPECT_GT(solver.initReport().mean_degree, 8.0);
    EXPECT_LT(solver.initReport().mean_degree, 16.0);
  }
}
