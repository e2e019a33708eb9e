// Render strands carried through the bundled scenes (issue "strands"):
// every strand within 2% of its rest length, no strand point inside the
// head or torso at any checked frame, and smooth.
#include "test_support.hpp"

#include "loosehair/render_strands.hpp"
#include "loosehair/strand_field.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
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

// Strands follow the particles where the hair splits: in back-hair-split a
// rod parts the back hair in two; the strands' points stay near particles
// (none left hanging in the gap) at every checked frame.
TEST(StrandScenario, StrandsFollowTheBackHairWhereItSplits) {
  SceneDesc scene = loadScene(lhtest::sourceDir() + "/data/scenes/back-hair-split.json");
  BuildReport build;
  Solver solver = buildSolver(scene, &build);
  RenderStrandOptions opt;
  opt.strands = 4000;
  const StrandField field = bindSceneStrands(scene, solver.particles(), build, opt, 2);
  std::vector<glm::vec3> pts;
  float worst_p95 = 0;
  for (int f = 1; f <= scene.frames; ++f) {
    for (int k = 0; k < build.substeps; ++k) solver.step();
    if (f % 30) continue;
    field.deform(solver, pts, 2);
    // distance of every 7th strand point to its nearest particle
    const auto& x = solver.particles().position;
    std::vector<float> d;
    for (std::size_t q = 0; q < pts.size(); q += 7) {
      float best = INFINITY;
      for (const glm::vec3& p : x) best = std::min(best, glm::length(p - pts[q]));
      d.push_back(best);
    }
    std::sort(d.begin(), d.end());
    worst_p95 = std::max(worst_p95, d[d.size() * 95 / 100]);
  }
  std::printf("back-hair-split: 95th percentile distance of a strand point to a particle %.4f m (spacing %.4f m)\n",
              worst_p95, build.mean_neighbor_distance);
  EXPECT_LT(worst_p95, 3.0f * build.mean_neighbor_distance);
}

// A styled scene draws its style's member strands, scaled to the count asked.
TEST(StrandScenario, AStyledSceneDrawsItsMemberStrands) {
  SceneDesc scene = loadScene(lhtest::sourceDir() + "/data/scenes/hang.json");
  scene.hair.particles = 3000;
  scene.hair.style = lhtest::sourceDir() + "/data/styles/bob.json";
  BuildReport build;
  Solver solver = buildSolver(scene, &build);
  RenderStrandOptions opt;
  opt.strands = 5000;
  opt.points = 20;
  const StrandField field = bindSceneStrands(scene, solver.particles(), build, opt, 2);
  EXPECT_GT(field.strandCount(), 3500u);
  EXPECT_LT(field.strandCount(), 6500u);
  for (std::size_t s = 0; s < field.strandCount(); ++s) ASSERT_EQ(field.rest().pointCount(s), 20u);
  std::vector<glm::vec3> pts;
  for (int k = 0; k < 15 * build.substeps; ++k) solver.step();
  field.deform(solver, pts, 2);
  EXPECT_LT(lhtest::strandLengthError(field, pts), 0.02f);
}

// A scene's "settle": the hair comes to rest before the first frame, with
// the clock held at 0, and the render strands follow it from the shape
// they were grown in. As grown, the bundled hang's hair fans out (the
// first frames showed it sticking out with a dark shadow over the face);
// settled, the strand tips hang nearer the head's axis and the particles
// are nearly still.
TEST(StrandScenario, SettledHairStartsAtRestAndItsStrandsFollow) {
  auto start = [](double settle, float& tip_spread, float& fastest, double& time) {
    SceneDesc scene = loadScene(lhtest::sourceDir() + "/data/scenes/hang.json");
    scene.hair.particles = 2500;
    scene.settle = settle;
    BuildReport build;
    Solver solver = buildSolver(scene, &build);
    EXPECT_EQ(settle > 0.0, build.grown != nullptr);
    time = solver.time();
    RenderStrandOptions opt;
    opt.strands = 2000;
    const StrandField field = bindSceneStrands(scene, solver.particles(), build, opt, 2);
    std::vector<glm::vec3> pts;
    field.deform(solver, pts, 2);
    double spread = 0;
    const StrandSet& r = field.rest();
    for (std::size_t s = 0; s < r.size(); ++s) {
      const glm::vec3 tip = pts[r.first[s + 1] - 1];
      spread += std::hypot(tip.x, tip.z);
    }
    tip_spread = static_cast<float>(spread / static_cast<double>(r.size()));
    fastest = 0.0f;
    for (const glm::vec3& v : solver.particles().velocity) fastest = std::max(fastest, glm::length(v));
  };
  float spread_grown = 0, spread_settled = 0, fast_grown = 0, fast_settled = 0;
  double t_grown = -1, t_settled = -1;
  start(0.0, spread_grown, fast_grown, t_grown);
  start(1.0, spread_settled, fast_settled, t_settled);
  std::printf("strand tips from the head's axis: %.1f mm as grown, %.1f mm settled; fastest particle %.3f m/s\n",
              1e3 * spread_grown, 1e3 * spread_settled, fast_settled);
  EXPECT_EQ(t_settled, 0.0) << "the clock starts at 0 after settling";
  EXPECT_LT(spread_settled, 0.9f * spread_grown) << "the strands kept the grown, fanned shape";
  EXPECT_LT(fast_settled, 0.5f);
}
