// Letting the physics finish a style (issue 44, settledKeyStrands): a
// sketch whose wisps stand off the head is simulated on a still head and
// its key strands read back where the hair came to lie. The settled style
// then lies where gravity puts it: simulated again it hardly moves, with
// shape keeping and without, while the sketch falls.
#include "style_fixtures.hpp"

#include "loosehair/scene.hpp"
#include "loosehair/solver.hpp"
#include "loosehair/style_editor.hpp"
#include "loosehair/style_settle.hpp"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>

using namespace loosehair;
using namespace lhtest::styles;

namespace {

// A sketch: two wisps whose key strands go straight out from the sphere,
// level, as a quick drawing would leave them.
Style sketch() {
  Style s = twoWispStyle();
  const HeadModel& h = sphereModel();
  for (Wisp& w : s.wisps) {
    const glm::vec3 root = w.key_strand[0], n = h.scalpNormal(regionRoot(w.region, h));
    glm::vec3 out(n.x, 0.0f, n.z);
    out = glm::length(out) > 0.1f ? glm::normalize(out) : glm::vec3(1.0f, 0.0f, 0.0f);
    w.key_strand = {root, root + 0.02f * n, root + 0.02f * n + 0.06f * out, root + 0.02f * n + 0.12f * out};
  }
  return s;
}

// The median distance the hair particles (roots excepted) move over
// `seconds` when the style is simulated, with its shape keeping or without.
float medianMove(const Style& style, bool shape_keeping, double seconds) {
  SceneDesc scene;
  static_cast<HeadDesc&>(scene) = style.head;
  scene.source = "test-settle";
  scene.hair.style_data = std::make_shared<const Style>(style);
  scene.hair.particles = 600;
  if (!shape_keeping) {
    scene.shape_keeping_auto = false;
    scene.sim.shape_keeping = 0.0f;
  }
  scene.sim.threads = 2;
  BuildReport build;
  Solver solver = buildSolver(scene, &build);
  const std::vector<glm::vec3> start = solver.particles().position;
  solver.advance(static_cast<int>(std::ceil(seconds / solver.params().time_step)));
  std::vector<float> moved;
  const Particles& p = solver.particles();
  for (std::size_t i = 0; i < p.size(); ++i)
    if (!p.is_root[i]) moved.push_back(glm::length(p.position[i] - start[i]));
  std::nth_element(moved.begin(), moved.begin() + static_cast<std::ptrdiff_t>(moved.size() / 2), moved.end());
  return moved[moved.size() / 2];
}

}  // namespace

TEST(StyleSettle, TheSettledStyleLiesWhereGravityPutsIt) {
  const HeadModel& h = sphereModel();
  const Style raw = sketch();
  SettleOptions o;
  o.seconds = 1.5;
  o.particles = 600;
  o.threads = 2;
  const std::vector<std::vector<glm::vec3>> keys = settledKeyStrands(raw, o);
  ASSERT_EQ(keys.size(), raw.wisps.size());
  StyleEditor ed(raw, h);
  ed.setKeyStrands(keys);
  const Style settled = ed.style();
  float fell = 0.0f;
  for (std::size_t w = 0; w < keys.size(); ++w) {
    ASSERT_GE(keys[w].size(), raw.wisps[w].key_strand.size());
    EXPECT_EQ(settled.wisps[w].key_strand[0], raw.wisps[w].key_strand[0]) << "the root stays on the region";
    for (std::size_t k = 1; k < keys[w].size(); ++k) EXPECT_GT(h.headDistance(keys[w][k]), 0.0f);
    fell = std::max(fell, raw.wisps[w].key_strand.back().y - keys[w].back().y);
  }
  EXPECT_GT(fell, 0.03f) << "the level sketch's tips fell";
  const float raw_plain = medianMove(raw, false, 1.0), settled_plain = medianMove(settled, false, 1.0);
  const float settled_kept = medianMove(settled, true, 1.0), raw_kept = medianMove(raw, true, 1.0);
  std::printf(
      "median move in 1 s: sketch %.1f mm, settled %.1f mm (no shape keeping); with shape keeping: sketch "
      "%.1f mm, settled %.1f mm; the tips fell %.0f mm\n",
      1e3f * raw_plain, 1e3f * settled_plain, 1e3f * raw_kept, 1e3f * settled_kept, 1e3f * fell);
  // The figure: under 5 mm median in the first second with shape
  // keeping. Shape keeping starts a style pre-stressed at rest, so the
  // sketch passes it too (printed above); what shows the settle is the
  // comparison without shape keeping below.
  EXPECT_LT(settled_kept, 0.005f);
  EXPECT_LT(settled_plain, 0.5f * raw_plain) << "it lies where gravity puts it: the sketch falls, it hardly moves";
  // one undo step takes the whole settle back
  ASSERT_TRUE(ed.undo());
  EXPECT_TRUE(ed.style() == raw);
  // what cannot be settled is refused, naming why
  Style none = raw;
  none.wisps.clear();
  EXPECT_THROW(settledKeyStrands(none), StyleError);
  SettleOptions bad = o;
  bad.seconds = 0.0;
  EXPECT_THROW(settledKeyStrands(raw, bad), StyleError);
  bad = o;
  bad.particles = 10;
  EXPECT_THROW(settledKeyStrands(raw, bad), StyleError);
}
