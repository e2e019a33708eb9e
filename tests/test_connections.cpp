// method.md §3.1: alignment, thresholds, pruning and the connectivity check.
#include "solver/connection_builder.hpp"
#include "solver/connection_slices.hpp"
#include "solver/pair_columns.hpp"
#include "util/random.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
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
  EXPECT_NEAR(alignment(down, tilted, glm::vec3(0, -0.01f, 0)), (1.0f + std::sqrt(0.5f)) / 2, 1e-6f);
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

// The solver's connection passes run over a sliced layout of the connections
// (connection_slices.hpp): every entry must be there once, in its list's
// order, at its particle's lane, and the padding must be recognisable.
TEST(ConnectionSlices, HoldEveryEntryOnceInListOrder) {
  Random rng(7);
  ConnectionSet c;
  const std::size_t n = 301;  // not a multiple of 16: the last slice is partial
  c.offset.push_back(0);
  for (std::size_t i = 0; i < n; ++i) {
    const auto degree = static_cast<std::uint32_t>(rng.uniform() * 21.0);  // 0..20
    const auto roots = static_cast<std::uint32_t>(rng.uniform() * (degree + 1));
    for (std::uint32_t e = 0; e < degree; ++e) c.partner.push_back(static_cast<std::uint32_t>(rng.uniform() * n) % n);
    c.tip_offset.push_back(c.offset.back() + std::min(roots, degree));
    c.offset.push_back(c.offset.back() + degree);
  }
  const ConnectionSlices s = sliceConnections(c, 64);
  constexpr std::size_t L = ConnectionSlices::kLanes;
  ASSERT_EQ(s.sliceCount(), (n + L - 1) / L);
  std::vector<int> seen(n, 0);
  std::vector<int> entry_seen(c.entryCount(), 0);
  std::size_t slots = 0;
  for (std::size_t sl = 0; sl < s.sliceCount(); ++sl) {
    const std::uint32_t rows = s.row_begin[sl + 1] - s.row_begin[sl];
    std::uint32_t longest = 0;
    for (std::size_t l = 0; l < L; ++l) {
      const std::size_t lane = sl * L + l;
      const std::uint32_t i = s.owner[lane];
      ASSERT_LT(i, n);
      const bool real = lane < n;
      if (real) ++seen[i];
      const std::uint32_t degree = real ? c.degree(i) : 0;
      EXPECT_EQ(s.degree[lane], static_cast<float>(degree)) << "lane " << lane;
      if (real) {
        EXPECT_EQ(s.root_degree[lane], static_cast<float>(c.tipBegin(i) - c.begin(i)));
      }
      longest = std::max(longest, degree);
      for (std::uint32_t r = 0; r < rows; ++r) {
        const std::size_t slot = (std::size_t{s.row_begin[sl]} + r) * L + l;
        ++slots;
        if (r < degree) {
          ASSERT_EQ(s.entry[slot], c.begin(i) + r) << "lane " << lane << " row " << r;
          EXPECT_EQ(s.partner[slot], c.partner[c.begin(i) + r]);
          ++entry_seen[s.entry[slot]];
        } else {
          EXPECT_EQ(s.entry[slot], ConnectionSlices::kPadding);
          EXPECT_EQ(s.partner[slot], i);  // a valid index for the gathers
        }
      }
    }
    EXPECT_EQ(rows, longest) << "slice " << sl << " has rows beyond its longest list";
  }
  for (std::size_t i = 0; i < n; ++i) EXPECT_EQ(seen[i], 1) << "particle " << i;
  for (std::size_t e = 0; e < c.entryCount(); ++e) EXPECT_EQ(entry_seen[e], 1) << "entry " << e;
  // sorting by degree within windows keeps the padding small
  EXPECT_LT(static_cast<double>(slots - c.entryCount()), 0.25 * static_cast<double>(slots));
  // arrange() moves a per-entry column into the layout
  std::vector<float> value(c.entryCount());
  for (std::size_t e = 0; e < value.size(); ++e) value[e] = static_cast<float>(e);
  const std::vector<float> arranged = s.arrange(value, -1.0f);
  for (std::size_t k = 0; k < arranged.size(); ++k)
    EXPECT_EQ(arranged[k], s.entry[k] == ConnectionSlices::kPadding ? -1.0f : static_cast<float>(s.entry[k]));
}

// The gathers copy every partner's record whether they prefetch ahead or
// not, and read no index past `readable` (the index column is allocated
// exactly that long, so an over-read shows under AddressSanitizer).
TEST(ConnectionSlices, GathersCopyEveryRecordWithAnyLookAhead) {
  Random rng(11);
  const std::size_t n = 997, count = 16 * 40;
  std::vector<float> rec(8 * n);
  for (float& f : rec) f = static_cast<float>(rng.uniform());
  for (const std::size_t readable :
       {std::size_t{0}, count, count + 3, count + kGatherAhead - 1, count + kGatherAhead + 17}) {
    std::vector<std::uint32_t> idx(std::max(readable, count));
    for (auto& j : idx) j = static_cast<std::uint32_t>(rng.uniform() * n) % n;
    std::vector<float> out(8 * count, -1.0f);
    gatherRows3(rec.data(), idx.data(), count, readable, &out[0], &out[count], &out[2 * count]);
    for (std::size_t k = 0; k < count; ++k)
      for (std::size_t c = 0; c < 3; ++c)
        ASSERT_EQ(out[c * count + k], rec[3 * idx[k] + c]) << "rows3 entry " << k << " readable " << readable;
    gatherRecords(rec.data(), idx.data(), count, readable, &out[0], &out[count], &out[2 * count], &out[3 * count]);
    for (std::size_t k = 0; k < count; ++k)
      for (std::size_t c = 0; c < 4; ++c)
        ASSERT_EQ(out[c * count + k], rec[4 * idx[k] + c]) << "records entry " << k << " readable " << readable;
    gatherRecordPairs(rec.data(), idx.data(), count, readable, out.data(), count);
    for (std::size_t k = 0; k < count; ++k)
      for (std::size_t c = 0; c < 8; ++c)
        ASSERT_EQ(out[c * count + k], rec[8 * idx[k] + c]) << "pairs entry " << k << " readable " << readable;
  }
}

// The pair loops' scratch columns: room for every pair in every column,
// 64-byte aligned rows, and an odd number of 64-byte lines from one column
// to the next, so that a block's columns fall into different sets of the
// first-level cache (with 1024 floats between them, all 17 hair-hair
// columns shared one set and that pass ran 1.7x slower).
TEST(PairColumns, ColumnsHoldEveryPairAndNeverAlignOnOneCacheSet) {
  for (const std::size_t pairs :
       {std::size_t{1}, std::size_t{16}, std::size_t{1000}, std::size_t{1024}, std::size_t{2048}, std::size_t{4093}}) {
    PairColumns col;
    col.reserve(pairs, 17);
    const std::size_t stride = col.stride();
    EXPECT_GE(stride, pairs);
    EXPECT_EQ(stride % 16, 0u) << pairs << " pairs";
    EXPECT_EQ((stride / 16) % 2, 1u) << pairs << " pairs: stride " << stride;
    EXPECT_EQ(col[1] - col[0], static_cast<std::ptrdiff_t>(stride));
    // growing keeps the property
    col.reserve(pairs + 100, 17);
    EXPECT_EQ((col.stride() / 16) % 2, 1u);
  }
}
