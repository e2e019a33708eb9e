// The styling mode's strand brushes and mirrored editing (issue 44): what a
// dab does to a key strand (brushedKeyStrand), and the partner a wisp's
// edits are mirrored onto (StyleEditor::mirrorPartner, mirroredOnto).
#include "style_fixtures.hpp"

#include "loosehair/strand_brushes.hpp"
#include "loosehair/style_editor.hpp"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

using namespace loosehair;
using namespace lhtest::styles;

namespace {

// straight out from a root on the sphere's side, 6 points 4 cm apart
struct Straight {
  std::vector<glm::vec3> key;
  glm::vec3 normal;
};
Straight straight() {
  const HeadModel& h = sphereModel();
  const glm::vec2 uv(0.2f, 0.5f);
  Straight s;
  s.normal = h.scalpNormal(uv);
  const glm::vec3 root = h.scalpPoint(uv);
  for (int j = 0; j < 6; ++j) s.key.push_back(root + (0.04f * static_cast<float>(j)) * s.normal);
  return s;
}

std::vector<float> spans(const std::vector<glm::vec3>& key) {
  std::vector<float> l;
  for (std::size_t k = 1; k < key.size(); ++k) l.push_back(glm::length(key[k] - key[k - 1]));
  return l;
}

BrushDab dab(StrandBrush b, std::size_t n, float weight) {
  BrushDab d;
  d.brush = b;
  d.weight.assign(n, weight);
  d.move.assign(n, glm::vec3(0.0f));
  d.strength = 1.0f;
  return d;
}

}  // namespace

TEST(StrandBrushes, CombPullsTheTipsMostAndKeepsTheSpans) {
  const HeadModel& h = sphereModel();
  const Straight s = straight();
  BrushDab d = dab(StrandBrush::Comb, s.key.size(), 1.0f);
  const glm::vec3 down(0.0f, -0.03f, 0.0f);
  d.move.assign(s.key.size(), down);
  const std::vector<glm::vec3> out = brushedKeyStrand(s.key, d, h, s.normal, StyleEditor::kClearance);
  EXPECT_EQ(out[0], s.key[0]) << "the root follows the region";
  const std::vector<float> a = spans(s.key), b = spans(out);
  for (std::size_t k = 0; k < a.size(); ++k) EXPECT_NEAR(b[k], a[k], 1e-5f) << "span " << k << " kept";
  float last = 0.0f;
  for (std::size_t k = 1; k < out.size(); ++k) {
    const float dropped = s.key[k].y - out[k].y;
    EXPECT_GT(dropped, last) << "point " << k << " follows the comb more than the one before";
    last = dropped;
  }
  // untouched: nothing moves
  d.weight.assign(s.key.size(), 0.0f);
  EXPECT_EQ(brushedKeyStrand(s.key, d, h, s.normal, StyleEditor::kClearance), s.key);
}

TEST(StrandBrushes, LengthGrowsAndCutsFromTheRoot) {
  const HeadModel& h = sphereModel();
  const Straight s = straight();
  const float total = 0.2f;
  BrushDab d = dab(StrandBrush::Length, s.key.size(), 1.0f);
  d.grow = 0.1f;
  const std::vector<glm::vec3> longer = brushedKeyStrand(s.key, d, h, s.normal, StyleEditor::kClearance);
  EXPECT_NEAR(glm::length(longer.back() - longer.front()), 1.1f * total, 1e-4f);
  d.grow = -0.1f;
  const std::vector<glm::vec3> shorter = brushedKeyStrand(s.key, d, h, s.normal, StyleEditor::kClearance);
  EXPECT_NEAR(glm::length(shorter.back() - shorter.front()), 0.9f * total, 1e-4f);
  // a strand is never cut below 1 cm, however hard the brush
  std::vector<glm::vec3> k = s.key;
  d.grow = -1.0f;
  for (int i = 0; i < 100; ++i) k = brushedKeyStrand(k, d, h, s.normal, StyleEditor::kClearance);
  EXPECT_GE(glm::length(k.back() - k.front()), 0.0099f);
}

TEST(StrandBrushes, PuffLiftsNearTheRootAndSmoothTakesOutKinks) {
  const HeadModel& h = sphereModel();
  // a strand lying down along the sphere, then out
  const Straight s = straight();
  std::vector<glm::vec3> lying = {s.key[0]};
  const glm::vec3 along = glm::normalize(glm::cross(s.normal, glm::vec3(0.0f, 0.0f, 1.0f)));
  for (int j = 1; j < 6; ++j) {
    const glm::vec3 p = s.key[0] + (0.04f * static_cast<float>(j)) * along;
    lying.push_back(keptOutsideHead(h, p, StyleEditor::kClearance));
  }
  const std::vector<glm::vec3> puffed =
      brushedKeyStrand(lying, dab(StrandBrush::Puff, lying.size(), 1.0f), h, s.normal, StyleEditor::kClearance);
  EXPECT_GT(h.headDistance(puffed[1]), h.headDistance(lying[1]) + 0.005f) << "lifted off the scalp near the root";
  const std::vector<float> a = spans(lying), b = spans(puffed);
  for (std::size_t k = 0; k < a.size(); ++k) EXPECT_NEAR(b[k], a[k], 1e-4f);
  // a kinked strand smoothed
  std::vector<glm::vec3> kinked = s.key;
  kinked[3] += 0.03f * along;
  const std::vector<glm::vec3> smoothed =
      brushedKeyStrand(kinked, dab(StrandBrush::Smooth, kinked.size(), 1.0f), h, s.normal, StyleEditor::kClearance);
  EXPECT_LT(sharpestTurn(smoothed), 0.8f * sharpestTurn(kinked));
  EXPECT_EQ(smoothed.back(), kinked.back()) << "the tip stays";
  // bad dabs are refused
  BrushDab bad = dab(StrandBrush::Comb, 3, 1.0f);
  EXPECT_THROW(brushedKeyStrand(s.key, bad, h, s.normal, StyleEditor::kClearance), StyleError);
  bad = dab(StrandBrush::Smooth, s.key.size(), 1.5f);
  EXPECT_THROW(brushedKeyStrand(s.key, bad, h, s.normal, StyleEditor::kClearance), StyleError);
  bad = dab(StrandBrush::Comb, s.key.size(), 1.0f);
  bad.move[2] = glm::vec3(NAN);
  EXPECT_THROW(brushedKeyStrand(s.key, bad, h, s.normal, StyleEditor::kClearance), StyleError);
  EXPECT_THROW(parseStrandBrush("rake"), StyleError);
  EXPECT_EQ(parseStrandBrush(strandBrushName(StrandBrush::Puff)), StrandBrush::Puff);
}

TEST(StrandBrushes, EveryPointBrushedIntoTheHeadIsPushedOut) {
  const HeadModel& h = sphereModel();
  const Straight s = straight();
  BrushDab d = dab(StrandBrush::Comb, s.key.size(), 1.0f);
  d.move.assign(s.key.size(), -0.3f * s.normal);  // straight back into the sphere
  const std::vector<glm::vec3> out = brushedKeyStrand(s.key, d, h, s.normal, StyleEditor::kClearance);
  for (std::size_t k = 1; k < out.size(); ++k) EXPECT_GT(h.headDistance(out[k]), 0.9f * StyleEditor::kClearance);
}

TEST(StrandBrushes, AMirroredWispFollowsItsPartnersEdits) {
  const HeadModel& h = sphereModel();
  StyleEditor ed(twoWispStyle(), h);
  const std::size_t m = ed.mirrorWisp(0);
  ASSERT_EQ(ed.mirrorPartner(0), m);
  ASSERT_EQ(ed.mirrorPartner(m), std::optional<std::size_t>(0));
  EXPECT_FALSE(ed.mirrorPartner(1).has_value()) << "wisp 1 has no wisp at its mirror image";
  // a drag of wisp 0, mirrored onto its partner in the same edit
  const std::vector<glm::vec3> moved =
      ed.dragged(ed.style().wisps[0].key_strand, 2, glm::vec3(0.0f, 0.02f, 0.01f), 0.05f);
  ed.setKeyStrandsOf({{0, moved}, {m, ed.mirroredOnto(moved, m)}});
  const float c = h.mirrorPlaneX();
  const auto& a = ed.style().wisps[0].key_strand;
  const auto& b = ed.style().wisps[m].key_strand;
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k)
    EXPECT_LT(glm::length(b[k] - glm::vec3(c - (a[k].x - c), a[k].y, a[k].z)), 1e-4f) << "point " << k;
  ASSERT_TRUE(ed.undo());
  EXPECT_FALSE(ed.style().wisps[0].key_strand == moved) << "one undo takes back both";
}
