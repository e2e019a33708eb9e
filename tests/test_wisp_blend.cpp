// Adjacent wisps meet as one head of hair (issue 44, WispParams::blend):
// members near the border between two wisps whose key strands fan out take
// a blend of both shapes (not across a parting), so the V-shaped bald gap between the wisps closes,
// while members near a wisp's own root keep its shape; blend 0 (and style
// files without the field) grow the seed's translated copies as before.
#include "style_fixtures.hpp"

#include "loosehair/file_io.hpp"
#include "loosehair/scalp_coverage.hpp"
#include "loosehair/strand_brushes.hpp"
#include "loosehair/style_editor.hpp"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

using namespace loosehair;
using namespace lhtest::styles;

namespace {

// Two regions side by side on the sphere's side, their key strands
// fanning out (`spread` 1: their tips 5 cm apart, relative to the roots) or
// parting (spread 4: 20 cm, more than half their length).
Style fanning(float blend, float spread = 1.0f) {
  const HeadModel& h = sphereModel();
  StyleEditor ed(emptyStyle(), h);
  WispParams p;
  p.density = 30.0f;
  p.offset_radius = 0.0f;
  p.length_variation = 0.0f;
  p.blend = blend;
  const WispRegion a = square({0.30f, 0.40f}, {0.40f, 0.55f}), b = square({0.40f, 0.40f}, {0.50f, 0.55f});
  for (const auto& [r, side] : {std::pair{a, -1.0f}, std::pair{b, 1.0f}}) {
    const glm::vec2 uv = regionRoot(r, h);
    const glm::vec3 root = h.scalpPoint(uv), n = h.scalpNormal(uv);
    const glm::vec3 key1 = root + 0.02f * n;
    glm::vec3 out(n.x, 0.0f, n.z);
    out = glm::length(out) > 0.1f ? glm::normalize(out) : glm::vec3(1.0f, 0.0f, 0.0f);
    const glm::vec3 key2 =
        keptOutsideHead(h, key1 + 0.05f * out + glm::vec3(0.0f, -0.08f, 0.015f * spread * side), 0.01f);
    const glm::vec3 key3 =
        keptOutsideHead(h, key2 + 0.02f * out + glm::vec3(0.0f, -0.1f, 0.01f * spread * side), 0.01f);
    ed.createWisp(r, p, {root, key1, key2, key3});
  }
  return ed.style();
}

// the smallest distance between a point of wisp 0's members and one of
// wisp 1's at the same fraction f of their length
float gapAt(const StrandSet& m, float f) {
  std::vector<glm::vec3> a, b;
  for (std::size_t k = 0; k < m.size(); ++k) {
    const std::size_t n = m.pointCount(k);
    const glm::vec3 p = m.points[m.first[k] + static_cast<std::size_t>(f * static_cast<float>(n - 1))];
    (m.wisp[k] == 0 ? a : b).push_back(p);
  }
  float best = INFINITY;
  for (const glm::vec3& p : a)
    for (const glm::vec3& q : b) best = std::min(best, glm::length(p - q));
  return best;
}

}  // namespace

TEST(WispBlend, MembersAtTheBorderBlendTheNeighboursShapesSoTheGapCloses) {
  const HeadModel& h = sphereModel();
  const StrandSet copies = buildMemberStrands(fanning(0.0f), h, 0.004f);
  const StrandSet blended = buildMemberStrands(fanning(1.0f), h, 0.004f);
  ASSERT_EQ(copies.size(), blended.size()) << "the same roots";
  const float gap0 = gapAt(copies, 0.9f), gap1 = gapAt(blended, 0.9f);
  std::printf("nearest members of the two wisps near their tips: %.1f mm as translated copies, %.1f mm blended\n",
              1e3f * gap0, 1e3f * gap1);
  EXPECT_LT(gap1, 0.5f * gap0) << "the gap between the fanning wisps closes";
  // a parting stays one: blended, the two would fall between them
  const float part0 = gapAt(buildMemberStrands(fanning(0.0f, 4.0f), h, 0.004f), 0.9f);
  const float part1 = gapAt(buildMemberStrands(fanning(1.0f, 4.0f), h, 0.004f), 0.9f);
  EXPECT_EQ(part1, part0) << "no blending across a parting";
  // the member at each region's root keeps (nearly) its own key strand's shape
  for (std::uint32_t w = 0; w < 2; ++w) {
    std::size_t first = 0;
    while (blended.wisp[first] != w) ++first;  // a wisp's first member stands at its region's root
    float worst = 0.0f;
    const std::size_t n = std::min(blended.pointCount(first), copies.pointCount(first));
    for (std::size_t j = 0; j < n; ++j)
      worst = std::max(worst,
                       glm::length(blended.points[blended.first[first] + j] - copies.points[copies.first[first] + j]));
    EXPECT_LT(worst, 0.01f) << "wisp " << w << "'s central member";
  }
  // a style file without the field grows the translated copies, as before
  Style saved = fanning(1.0f);
  const std::string path = ::testing::TempDir() + "/blend-absent.json";
  saveStyle(saved, path);
  std::string text = readRegularFile(path, kMaxTextFileBytes);
  for (std::size_t at; (at = text.find("\"blend\"")) != std::string::npos;) {
    const std::size_t end = text.find_first_of(",}", at);
    text.erase(at, end - at + (text[end] == ',' ? 1 : 0));
  }
  writeFileAtomically(path, {text});
  const Style old = loadStyle(path);
  EXPECT_EQ(old.wisps[0].params.blend, 0.0f);
  const StrandSet again = buildMemberStrands(old, h, 0.004f);
  EXPECT_EQ(again.points, copies.points);
}

TEST(ScalpCoverageMeasure, ShareOfTheScalpNearARoot) {
  const HeadModel& h = sphereModel();
  // nothing grown: nothing covered; one small wisp: a little; a wisp over
  // the whole scalp: all of it
  EXPECT_EQ(scalpCoverage(h, {}).covered, 0.0);
  StyleEditor ed(emptyStyle(), h);
  WispParams p;
  p.density = 40.0f;
  ed.createWisp(square({0.45f, 0.45f}, {0.55f, 0.55f}), p);
  auto rootsOf = [](const StrandSet& m) {
    std::vector<glm::vec3> r;
    for (std::size_t k = 0; k < m.size(); ++k) r.push_back(m.points[m.first[k]]);
    return r;
  };
  const ScalpCoverage small = scalpCoverage(h, rootsOf(buildMemberStrands(ed.style(), h)));
  ed.createWisp(square({0.0f, 0.0f}, {1.0f, 1.0f}), p);
  const ScalpCoverage all = scalpCoverage(h, rootsOf(buildMemberStrands(ed.style(), h)));
  std::printf("covered: one small wisp %.1f %%, the whole scalp %.1f %%\n", 100 * small.covered, 100 * all.covered);
  EXPECT_GT(small.covered, 0.0);
  EXPECT_LT(small.covered, 0.2);
  EXPECT_EQ(small.bare.size(),
            small.samples - static_cast<std::size_t>(std::lround(small.covered * static_cast<double>(small.samples))));
  EXPECT_GT(all.covered, 0.97);
  EXPECT_THROW(scalpCoverage(h, {}, 0.0f), std::invalid_argument);
  EXPECT_THROW(scalpCoverage(h, {}, 0.005f, 0), std::invalid_argument);
}

// The hairline (WispParams::edge_ramp): members thin out towards the edge of
// the hair, not along the border between two wisps.
TEST(WispHairline, MembersThinOutTowardsTheEdgeOfTheHairNotBetweenWisps) {
  const HeadModel& h = sphereModel();
  auto grown = [&](float ramp) {
    StyleEditor ed(emptyStyle(), h);
    WispParams p;
    p.density = 40.0f;
    p.edge_ramp = ramp;
    ed.createWisp(square({0.0f, 0.0f}, {0.5f, 1.0f}), p);
    ed.createWisp(square({0.5f, 0.0f}, {1.0f, 1.0f}), p);
    return buildMemberStrands(ed.style(), h, 0.02f);
  };
  // roots near the scalp square's edge (the hair's edge: the scalp maps its
  // boundary to the square's) and near the wisps' shared border u = 1/2
  auto count = [](const StrandSet& m) {
    std::size_t edge = 0, border = 0;
    for (const glm::vec2 uv : m.root_uv) {
      const float to_edge = std::min({uv.x, 1.0f - uv.x, uv.y, 1.0f - uv.y});
      edge += to_edge < 0.02f ? 1 : 0;
      border += std::abs(uv.x - 0.5f) < 0.02f && to_edge > 0.15f ? 1 : 0;
    }
    return std::pair{edge, border};
  };
  const auto [edge0, border0] = count(grown(0.0f));
  const auto [edge1, border1] = count(grown(0.01f));
  std::printf("roots near the hair's edge: %zu without the ramp, %zu with; along the wisps' border: %zu, %zu\n", edge0,
              edge1, border0, border1);
  ASSERT_GT(edge0, 20u);
  ASSERT_GT(border0, 20u);
  EXPECT_LT(static_cast<double>(edge1), 0.6 * static_cast<double>(edge0)) << "the hairline thins out";
  EXPECT_GT(static_cast<double>(border1), 0.85 * static_cast<double>(border0)) << "no thinning between wisps";
}
