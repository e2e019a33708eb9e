// method.md §1 step 1: the hashed voxel grid finds exactly the brute-force
// neighbours, in a stable order that does not depend on the thread count.
#include "solver/neighbor_grid.hpp"
#include "util/random.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

using loosehair::NeighborGrid;
using loosehair::Random;

namespace {

std::vector<std::vector<std::uint32_t>> bruteForce(const std::vector<glm::vec3>& x, float radius) {
  std::vector<std::vector<std::uint32_t>> out(x.size());
  for (std::uint32_t i = 0; i < x.size(); ++i)
    for (std::uint32_t j = 0; j < x.size(); ++j) {
      if (i == j) continue;
      const glm::vec3 d = x[j] - x[i];
      if (d.x * d.x + d.y * d.y + d.z * d.z < radius * radius) out[i].push_back(j);
    }
  return out;
}

// Returns whether the dense layout was used.
bool expectMatchesBruteForce(const std::vector<glm::vec3>& x, float radius) {
  const auto expected = bruteForce(x, radius);
  NeighborGrid one, two, three, narrow;
  one.build(x, radius, 1);
  two.build(x, radius, 2);
  three.build(x, radius, 3);  // more threads than cores: chunks go to threads in any order
  // The 4-wide candidate test gives the same lists as the AVX-512 one.
  NeighborGrid::setWideSearch(false);
  narrow.build(x, radius, 2);
  NeighborGrid::setWideSearch(true);
  std::size_t differ = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const auto a = one.neighbors(i), d = narrow.neighbors(i);
    differ += std::equal(a.begin(), a.end(), d.begin(), d.end()) ? 0 : 1;
  }
  EXPECT_EQ(differ, 0u) << "points whose lists differ between the candidate tests";
  // Lists of positions in the search order name the same points in the
  // same order, with both candidate tests.
  for (bool wide : {true, false}) {
    NeighborGrid::setWideSearch(wide);
    NeighborGrid positions;
    positions.build(x, radius, 2, NeighborGrid::ListIndex::SearchOrder);
    NeighborGrid::setWideSearch(true);
    const auto order = positions.searchOrder();
    std::size_t mismatched = 0;
    for (std::size_t k = 0; k < x.size(); ++k) {
      const auto list = positions.list(k), want = one.neighbors(order[k]);
      std::vector<std::uint32_t> named;
      for (std::uint32_t q : list) named.push_back(order[q]);
      mismatched += std::equal(named.begin(), named.end(), want.begin(), want.end()) ? 0 : 1;
    }
    EXPECT_EQ(mismatched, 0u) << "search-order lists that name other points (wide test " << wide << ")";
  }
  EXPECT_EQ(one.pointCount(), x.size());
  std::size_t total = 0, wrong = 0;
  for (std::size_t i = 0; i < x.size() && wrong < 5; ++i) {
    const auto a = one.neighbors(i), b = two.neighbors(i), c = three.neighbors(i);
    // same order for any thread count
    const bool same_order =
        std::equal(a.begin(), a.end(), b.begin(), b.end()) && std::equal(a.begin(), a.end(), c.begin(), c.end());
    EXPECT_TRUE(same_order) << "point " << i;
    std::vector<std::uint32_t> got(a.begin(), a.end());
    std::sort(got.begin(), got.end());
    EXPECT_EQ(got, expected[i]) << "point " << i;
    wrong += (!same_order || got != expected[i]) ? 1 : 0;
    total += got.size();
  }
  EXPECT_EQ(one.pairCount(), total);
  EXPECT_EQ(one.usedDenseLayout(), two.usedDenseLayout());
  return one.usedDenseLayout();
}

}  // namespace

TEST(NeighborGrid, RandomPoints) {
  // Whether the comparisons of the candidate tests had the AVX-512 path to
  // compare (in the test's XML output; without it both builds run the 4-wide test).
  RecordProperty("avx512_candidate_test", NeighborGrid::wideSearchAvailable() ? "yes" : "no");
  Random rng(1);
  std::vector<glm::vec3> x(3000);
  for (auto& p : x) p = glm::vec3(rng.uniform(-0.2, 0.2), rng.uniform(-0.3, 0.1), rng.uniform(-0.2, 0.2));
  EXPECT_TRUE(expectMatchesBruteForce(x, 0.03f)) << "a compact cloud uses the dense layout";
}

TEST(NeighborGrid, ClusteredPoints) {
  Random rng(2);
  std::vector<glm::vec3> x;
  for (int c = 0; c < 5; ++c) {
    const glm::vec3 centre(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    for (int k = 0; k < 300; ++k)
      x.push_back(centre + glm::vec3(rng.uniform(-1e-3, 1e-3), rng.uniform(-1e-3, 1e-3), rng.uniform(-1e-3, 1e-3)));
  }
  // many exact duplicates too
  for (int k = 0; k < 50; ++k) x.push_back(x[static_cast<std::size_t>(k)]);
  EXPECT_FALSE(expectMatchesBruteForce(x, 0.01f)) << "a sparse box uses the hashed layout";
}

TEST(NeighborGrid, PointsOnCellBoundaries) {
  const float r = 0.25f;
  std::vector<glm::vec3> x;
  for (int i = -4; i <= 4; ++i)
    for (int j = -4; j <= 4; ++j)
      for (int k = -2; k <= 2; ++k) x.emplace_back(i * r, j * r, k * r * 0.5f);
  // exactly at distance r (excluded) and just inside
  x.emplace_back(0.0f, 0.0f, 0.0f);
  x.emplace_back(std::nextafter(r, 0.0f), 0.0f, 0.0f);
  EXPECT_TRUE(expectMatchesBruteForce(x, r));
}

TEST(NeighborGrid, FarOutliersDoNotGrowMemoryAndStayCorrect) {
  Random rng(3);
  std::vector<glm::vec3> x(500);
  for (auto& p : x) p = glm::vec3(rng.uniform(0, 0.1), rng.uniform(0, 0.1), rng.uniform(0, 0.1));
  x.emplace_back(1e7f, -3e6f, 5e5f);
  x.emplace_back(1e7f + 1e-3f, -3e6f, 5e5f);  // its neighbour, far from the rest
  x.emplace_back(-1e30f, 1e30f, 0.0f);
  x.emplace_back(1e30f, 1e30f, 1e30f);
  EXPECT_FALSE(expectMatchesBruteForce(x, 0.02f));
  NeighborGrid g;
  g.build(x, 0.02f, 2);
  EXPECT_LE(g.cellCount(), x.size());
}

TEST(NeighborGrid, NonFinitePointsHaveNoNeighbours) {
  std::vector<glm::vec3> x = {{0, 0, 0}, {0.001f, 0, 0}, {NAN, 0, 0}, {INFINITY, 0, 0}};
  NeighborGrid g;
  g.build(x, 0.01f, 2);
  EXPECT_EQ(g.neighbors(0).size(), 1u);
  EXPECT_EQ(g.neighbors(2).size(), 0u);
  EXPECT_EQ(g.neighbors(3).size(), 0u);
}

TEST(NeighborGrid, EmptyAndSinglePoint) {
  NeighborGrid g;
  std::vector<glm::vec3> none;
  g.build(none, 0.1f, 2);
  EXPECT_EQ(g.pointCount(), 0u);
  EXPECT_EQ(g.pairCount(), 0u);
  std::vector<glm::vec3> one = {{1, 2, 3}};
  g.build(one, 0.1f, 2);
  EXPECT_EQ(g.neighbors(0).size(), 0u);
}

TEST(NeighborGrid, RebuildAfterMotion) {
  Random rng(4);
  std::vector<glm::vec3> x(800);
  for (auto& p : x) p = glm::vec3(rng.uniform(0, 0.2), rng.uniform(0, 0.2), rng.uniform(0, 0.2));
  NeighborGrid g;
  g.build(x, 0.03f, 2);
  for (auto& p : x) p += glm::vec3(rng.uniform(-0.05, 0.05), 0.0f, rng.uniform(-0.05, 0.05));
  g.build(x, 0.03f, 2);
  const auto expected = bruteForce(x, 0.03f);
  for (std::size_t i = 0; i < x.size(); ++i) {
    std::vector<std::uint32_t> got(g.neighbors(i).begin(), g.neighbors(i).end());
    std::sort(got.begin(), got.end());
    ASSERT_EQ(got, expected[i]);
  }
}

// The solver shares its pair loops among threads by pairBalancedPart: the
// parts must cover the search order once, in order, starting at multiples of
// kPartGrain, with about equal pairs even where the point density differs a
// lot, and also when there are only a few chunks of points.
TEST(NeighborGrid, PairBalancedPartsCoverTheSearchOrderWithEqualPairs) {
  for (const auto& [dense, sparse] : {std::pair{12000, 12000}, std::pair{700, 1300}}) {
    SCOPED_TRACE(dense + sparse);
    Random rng(11);
    std::vector<glm::vec3> x;
    // a dense slab at low z (first in the search order) above a sparse block
    const float side = dense > 5000 ? 1.0f : 0.3f;
    for (int k = 0; k < dense; ++k) x.emplace_back(rng.uniform(0, side), rng.uniform(0, side), rng.uniform(0, 0.05));
    for (int k = 0; k < sparse; ++k) x.emplace_back(rng.uniform(0, side), rng.uniform(0, side), rng.uniform(0.5, 1.5));
    NeighborGrid g;
    g.build(x, 0.03f, 2, NeighborGrid::ListIndex::SearchOrder);
    const std::size_t n = x.size(), total = g.pairCount();
    constexpr std::size_t grain = NeighborGrid::kPartGrain;
    std::size_t max_grain_pairs = 0;
    for (std::size_t c = 0; c * grain < n; ++c) {
      std::size_t pairs = 0;
      for (std::size_t k = c * grain; k < std::min(n, (c + 1) * grain); ++k) pairs += g.list(k).size();
      max_grain_pairs = std::max(max_grain_pairs, pairs);
    }
    ASSERT_GT(total, 0u);
    ASSERT_LT(max_grain_pairs * 10, total);  // the split can be near equal
    for (int parts : {1, 2, 3, 5}) {
      std::size_t next = 0;
      for (int p = 0; p < parts; ++p) {
        const auto [first, second] = g.pairBalancedPart(p, parts);
        EXPECT_EQ(first, next) << "part " << p << " of " << parts;
        EXPECT_LE(first, second);
        EXPECT_TRUE(second == n || second % grain == 0) << second;
        std::size_t pairs = 0;
        for (std::size_t k = first; k < second; ++k) pairs += g.list(k).size();
        const double share = static_cast<double>(total) / parts;
        // each end within half a grain's pairs of its ideal place
        EXPECT_NEAR(static_cast<double>(pairs), share, static_cast<double>(max_grain_pairs))
            << "part " << p << " of " << parts;
        next = second;
      }
      EXPECT_EQ(next, n) << parts << " parts";
    }
    // An equal split by points would not do: the dense half holds most pairs.
    std::size_t first_half = 0;
    for (std::size_t k = 0; k < n / 2; ++k) first_half += g.list(k).size();  // the dense points and more
    EXPECT_GT(first_half, 2 * (total - first_half));
  }
}
