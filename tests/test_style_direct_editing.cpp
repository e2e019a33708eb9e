// Styling by hand (issue 44): what the view's drags and the new-wisp button
// do to a style, tested on the editor the viewer calls. New wisps hang as
// hair does, clear of the head; a dragged control point pulls the points
// after it with a falloff, so the strand bends instead of kinking; dragged
// and added points are kept outside the head; a whole drag is one undo step.
#include "style_fixtures.hpp"

#include "loosehair/style_editor.hpp"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

using namespace loosehair;
using namespace lhtest::styles;

namespace {

float length(const std::vector<glm::vec3>& key) {
  float l = 0.0f;
  for (std::size_t k = 1; k < key.size(); ++k) l += glm::length(key[k] - key[k - 1]);
  return l;
}

}  // namespace

TEST(StyleDirectEditing, NewWispsHangUnderGravityClearOfTheHead) {
  const HeadModel& h = sphereModel();
  StyleEditor ed(emptyStyle(), h);
  int hanging = 0, wisps = 0;
  for (float u : {0.2f, 0.5f, 0.8f})
    for (float v : {0.2f, 0.5f, 0.8f}) {
      const std::size_t w = ed.createWisp(square({u - 0.05f, v - 0.05f}, {u + 0.05f, v + 0.05f}));
      const std::vector<glm::vec3>& key = ed.style().wisps[w].key_strand;
      ++wisps;
      ASSERT_GE(key.size(), 3u);
      EXPECT_NEAR(length(key), StyleEditor::kNewWispLength, 0.15f * StyleEditor::kNewWispLength)
          << "a chord of the bent strand, a little shorter than it";
      for (std::size_t k = 1; k < key.size(); ++k)
        EXPECT_GT(h.headDistance(key[k]), 0.5f * StyleEditor::kClearance) << "wisp " << w << " point " << k;
      // down, not up: the tip below the root, and the last span pointing down
      EXPECT_LT(key.back().y, key.front().y) << "wisp " << w;
      const glm::vec3 last = glm::normalize(key.back() - key[key.size() - 2]);
      hanging += last.y < -0.5f ? 1 : 0;
      EXPECT_LT(sharpestTurn(key), 60.0f) << "wisp " << w << ": smooth, no spike";
    }
  EXPECT_GE(hanging, wisps - 1) << "the ends hang down (one on the crown may still lie along the scalp)";
  // its length is a parameter, checked
  const std::size_t w = ed.createWisp(square({0.4f, 0.4f}, {0.5f, 0.5f}), {}, {}, "long", 0.4f);
  EXPECT_NEAR(length(ed.style().wisps[w].key_strand), 0.4f, 0.06f);
  EXPECT_THROW(ed.createWisp(square({0.4f, 0.4f}, {0.5f, 0.5f}), {}, {}, "", 0.0f), StyleError);
  EXPECT_THROW(ed.createWisp(square({0.4f, 0.4f}, {0.5f, 0.5f}), {}, {}, "", NAN), StyleError);
}

TEST(StyleDirectEditing, ADraggedPointPullsThePointsAfterItSoTheStrandBends) {
  const HeadModel& h = sphereModel();
  Style s = twoWispStyle();
  StyleEditor ed(s, h);
  // straight out from the root along the normal, 6 points 4 cm apart
  const glm::vec3 root = ed.style().wisps[0].key_strand[0], out = glm::normalize(root);
  std::vector<glm::vec3> key;
  for (int j = 0; j < 6; ++j) key.push_back(root + (0.04f * static_cast<float>(j)) * out);
  ed.setKeyStrand(0, key);
  const std::size_t k = 2;
  // sideways, across the strand: nothing is pushed out
  const glm::vec3 side = glm::normalize(glm::cross(out, glm::vec3(0.0f, 1.0f, 0.0f)));
  const glm::vec3 offset = 0.03f * side;
  const std::vector<glm::vec3> soft = ed.dragged(key, k, offset, 0.05f);
  const std::vector<glm::vec3> alone = ed.dragged(key, k, offset, 0.0f);
  ASSERT_EQ(soft.size(), key.size());
  for (std::size_t j = 0; j < k; ++j) EXPECT_EQ(soft[j], key[j]) << "points before the dragged one stay";
  EXPECT_LT(glm::length(soft[k] - (key[k] + offset)), 1e-6f) << "the dragged point goes where the mouse takes it";
  float last = 1.0f;
  for (std::size_t j = k + 1; j < key.size(); ++j) {
    const float followed = glm::dot(soft[j] - key[j], side) / 0.03f;
    EXPECT_GT(followed, 0.0f) << "point " << j << " follows";
    EXPECT_LT(followed, last) << "point " << j << " follows less than the one before";
    last = followed;
  }
  for (std::size_t j = k + 1; j < key.size(); ++j) EXPECT_EQ(alone[j], key[j]) << "falloff 0: the point alone";
  std::printf("sharpest turn: dragged alone %.1f deg, with the falloff %.1f deg\n", sharpestTurn(alone),
              sharpestTurn(soft));
  EXPECT_LT(sharpestTurn(soft), sharpestTurn(alone)) << "the falloff bends the strand instead of kinking it";
  // the whole strand but its root
  const std::vector<glm::vec3> whole = ed.dragged(key, 1, offset, INFINITY);
  for (std::size_t j = 1; j < key.size(); ++j) EXPECT_LT(glm::length(whole[j] - (key[j] + offset)), 1e-6f);
  EXPECT_THROW(ed.dragged(key, 0, offset, 0.05f), StyleError) << "the root follows the region";
  EXPECT_THROW(ed.dragged(key, 2, glm::vec3(NAN), 0.05f), StyleError);
}

TEST(StyleDirectEditing, DraggedAndAddedPointsAreKeptOutsideTheHead) {
  const HeadModel& h = sphereModel();
  StyleEditor ed(twoWispStyle(), h);
  const std::vector<glm::vec3> key = ed.style().wisps[0].key_strand;
  // dragged towards the sphere's centre, deep inside
  const std::size_t k = key.size() - 1;
  const std::vector<glm::vec3> in = ed.dragged(key, k, -key[k] * 0.9f, 0.05f);
  for (std::size_t j = 1; j < in.size(); ++j) EXPECT_GT(h.headDistance(in[j]), 0.9f * StyleEditor::kClearance);
  ed.setKeyStrand(0, in);  // accepted: nothing inside
  // a strand whose last span points into the head: a point added after its
  // tip is moved out, not refused
  std::vector<glm::vec3> into = {key[0], key[0] + 0.03f * h.scalpNormal(regionRoot(ed.style().wisps[0].region, h))};
  into.push_back(into[1] - 0.025f * glm::normalize(into[1]));
  ed.setKeyStrand(0, into);
  const std::size_t n = ed.style().wisps[0].key_strand.size();
  ASSERT_NO_THROW(ed.addControlPoint(0, n));
  const glm::vec3 added = ed.style().wisps[0].key_strand.back();
  EXPECT_GT(h.headDistance(added), 0.9f * StyleEditor::kClearance);
}

TEST(StyleDirectEditing, AWholeDragIsOneUndoStep) {
  const HeadModel& h = sphereModel();
  StyleEditor ed(twoWispStyle(), h);
  const Style before = ed.style();
  const std::vector<glm::vec3> start = before.wisps[1].key_strand;
  // a drag: many moves, each computed from where the drag started
  for (int step = 1; step <= 10; ++step)
    ed.setKeyStrand(1, ed.dragged(start, 2, glm::vec3(0.003f * static_cast<float>(step), 0.0f, 0.0f), 0.05f), step > 1);
  const Style after = ed.style();
  EXPECT_FALSE(after == before);
  ASSERT_TRUE(ed.undo());
  EXPECT_TRUE(ed.style() == before) << "one undo takes the whole drag back";
  ASSERT_TRUE(ed.redo());
  EXPECT_TRUE(ed.style() == after);
  // a drag after another edit, or on another wisp, is an undo step of its own
  ed.setColour(glm::vec3(0.5f));
  ed.setKeyStrand(1, ed.dragged(start, 2, glm::vec3(0.0f, 0.0f, 0.01f), 0.05f), true);
  ASSERT_TRUE(ed.undo());
  EXPECT_TRUE(ed.style().colour == glm::vec3(0.5f)) << "the amend did not join the colour's edit";
  ed.setKeyStrand(0, ed.dragged(ed.style().wisps[0].key_strand, 1, glm::vec3(0.0f, 0.0f, 0.01f), 0.05f), true);
  ed.setKeyStrand(1, ed.dragged(start, 1, glm::vec3(0.0f, 0.0f, 0.01f), 0.05f), true);
  ASSERT_TRUE(ed.undo());
  EXPECT_FALSE(ed.style().wisps[0].key_strand == ed.style().wisps[1].key_strand);
  EXPECT_TRUE(ed.style().wisps[1].key_strand == after.wisps[1].key_strand) << "wisp 1's drag was its own step";
  // the root stays on the region whatever the drag says
  std::vector<glm::vec3> moved = ed.style().wisps[0].key_strand;
  const glm::vec3 root = moved[0];
  moved[0] += glm::vec3(0.05f);
  ed.setKeyStrand(0, moved);
  EXPECT_EQ(ed.style().wisps[0].key_strand[0], root);
}

TEST(StyleDirectEditing, ATieThatHoldsNoHairIsRefusedSayingWhereToPutIt) {
  const HeadModel& h = sphereModel();
  StyleEditor ed(twoWispStyle(), h);
  const std::vector<glm::vec3>& key = ed.style().wisps[0].key_strand;
  HairTie off;  // beyond the tip, where no key strand passes
  off.center = key.back() + 0.2f * glm::normalize(key.back() - key.front());
  off.axis = glm::vec3(0.0f, 1.0f, 0.0f);
  off.radius = 0.01f;
  try {
    ed.addTie(off);
    FAIL() << "a tie round nothing was accepted";
  } catch (const StyleError& e) {
    EXPECT_NE(std::string(e.what()).find("place it where the key strands pass"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(ed.canUndo() && ed.style().ties.size() > 0) << "nothing was added";
  // one round the key strand's middle is taken
  HairTie on;
  on.center = 0.5f * (key[1] + key[2]);
  on.axis = glm::normalize(key[2] - key[1]);
  on.radius = 0.01f;
  EXPECT_NO_THROW(ed.addTie(on));
  EXPECT_EQ(ed.style().ties.size(), 1u);
}

TEST(StyleDirectEditing, AStrandDraggedAcrossTheHeadGoesRoundItSoTheStyleStillLoads) {
  const HeadModel& h = sphereModel();
  StyleEditor ed(twoWispStyle(), h);
  const std::vector<glm::vec3> key = ed.style().wisps[0].key_strand;
  // every point but the root carried to the far side of the sphere: each
  // lies outside, but the spline from the root to them cuts through it
  std::vector<glm::vec3> across = key;
  for (std::size_t k = 1; k < across.size(); ++k) across[k] = ed.keptOutside(glm::vec3(-key[k].x, key[k].y, -key[k].z));
  float deepest = 0.0f;
  for (const glm::vec3& p : sampleKeyStrand(across, 8)) deepest = std::min(deepest, h.headDistance(p));
  ASSERT_LT(deepest, -0.003f) << "the spline as given would cut into the head";
  ed.setKeyStrand(0, across);
  const std::vector<glm::vec3>& kept = ed.style().wisps[0].key_strand;
  EXPECT_GT(kept.size(), across.size()) << "control points were added";
  for (const glm::vec3& p : across)
    EXPECT_NE(std::find(kept.begin(), kept.end(), p), kept.end()) << "the given points stay";
  Style s = ed.style();
  s.source = "dragged";
  EXPECT_NO_THROW(checkStyle(s, h)) << "what the editor holds passes the style file's check";
  // a single point moved across does the same
  ed.undo();
  ed.setControlPoint(0, 1, across[1]);
  s = ed.style();
  EXPECT_NO_THROW(checkStyle(s, h));
}

TEST(StyleDirectEditing, ATieWhoseRingReachesIntoTheHeadIsRefusedAsItsFileWouldBe) {
  const HeadModel& h = sphereModel();
  StyleEditor ed(twoWispStyle(), h);
  const std::vector<glm::vec3> key = ed.style().wisps[0].key_strand;
  HairTie tie;  // round the key strand where it lies on the head
  tie.center = key[1];
  tie.axis = glm::normalize(key[2] - key[1]);
  tie.radius = 2.0f * h.headDistance(key[1]) + 0.01f;
  try {
    ed.addTie(tie);
    FAIL() << "a ring reaching into the head was accepted";
  } catch (const StyleError& e) {
    EXPECT_NE(std::string(e.what()).find("would reach into the head"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(ed.style().ties.empty());
  // the same ring with the strand gathered off the head, in one edit
  const glm::vec3 n = glm::normalize(key[1]);  // the sphere's outward normal there
  tie.center = key[1] + (tie.radius + 0.002f) * n;
  std::vector<glm::vec3> gathered = key;
  gathered.insert(gathered.begin() + 2, tie.center);
  ASSERT_NO_THROW(ed.addTie(tie, {{0, gathered}}));
  EXPECT_EQ(ed.style().ties.size(), 1u);
  ed.undo();
  EXPECT_TRUE(ed.style().ties.empty());
  EXPECT_EQ(ed.style().wisps[0].key_strand, key) << "the tie and the gathering are one undo step";
}
