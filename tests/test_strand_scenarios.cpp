// Render strands carried through the bundled scenes (issue "strands"):
// every strand within 2% of its rest length, no strand point inside the
// head or torso at any checked frame, and smooth.
#include "test_support.hpp"

#include "loosehair/render_strands.hpp"
#include "loosehair/strand_field.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

using namespace loosehair;

namespace {

void carryThrough(const std::string& name, int every) {
  SceneDesc scene = loadScene(lhtest::sourceDir() + "/data/scenes/" + name);
  BuildReport build;
  Solver solver = buildSolver(scene, &build);
  RenderStrandOptions opt;
  opt.strands = 10000;
  const StrandField field = bindSceneStrands(scene, solver.particles(), build, opt, 2);
  std::vector<glm::vec3> pts;
  std::vector<float> phi, turns;
  float worst_len = 0, min_phi = INFINITY;
  const StrandSet& r = field.rest();
  for (int f = 1; f <= scene.frames; ++f) {
    for (int k = 0; k < build.substeps; ++k) solver.step();
    if (f % every && f != scene.frames) continue;
    field.deform(solver, pts, 2);
    worst_len = std::max(worst_len, lhtest::strandLengthError(field, pts));
    lhtest::extraTurns(field, pts, turns);
    solver.bodyDistance(pts, solver.time(), phi);
    for (std::size_t s = 0; s < r.size(); ++s)  // roots lie on the scalp itself
      for (std::uint32_t q = r.first[s] + 1; q < r.first[s + 1]; ++q) min_phi = std::min(min_phi, phi[q]);
  }
  std::sort(turns.begin(), turns.end());
  const float p99 = turns[turns.size() * 99 / 100];
  std::printf("%s: %zu strands, worst length error %.4f, nearest body %.2e m, extra turn p50 %.1f p99 %.1f deg\n",
              name.c_str(), field.strandCount(), worst_len, min_phi, turns[turns.size() / 2], p99);
  EXPECT_LT(worst_len, 0.02f) << name;
  EXPECT_GE(min_phi, 0.0f) << name;
  EXPECT_LT(p99, 60.0f) << name;
}

}  // namespace

TEST(StrandScenario, HangKeepsStrandLengthsAndBodiesOut) { carryThrough("hang.json", 10); }
TEST(StrandScenario, HeadShakeKeepsStrandLengthsAndBodiesOut) { carryThrough("head-shake.json", 10); }
TEST(StrandScenario, WindKeepsStrandLengthsAndBodiesOut) { carryThrough("wind.json", 10); }
