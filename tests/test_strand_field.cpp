// Strands carried by the particle field (loosehair/strand_field.hpp): rigid
// motions carry them rigidly, lengths stay within the tolerance, no point
// ends inside a body, strands stay smooth, same bits for any thread count.
#include "test_support.hpp"

#include "loosehair/head_model.hpp"
#include "loosehair/render_strands.hpp"
#include "loosehair/strand_field.hpp"

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstring>

using namespace loosehair;

namespace {

struct Bound {
  SceneDesc scene;
  Solver solver;
  BuildReport build;
  StrandField field;
};

Bound bindSphere(int particles, std::size_t strands, const std::string& motion = R"({"type": "still"})") {
  SceneDesc scene = lhtest::sphereScene(particles, "{}", motion);
  BuildReport build;
  Solver solver = buildSolver(scene, &build);
  RenderStrandOptions opt;
  opt.strands = strands;
  opt.points = 24;
  StrandField field = bindSceneStrands(scene, solver.particles(), build, opt, 2);
  return Bound{std::move(scene), std::move(solver), build, std::move(field)};
}

using lhtest::strandLengthError;
using lhtest::extraTurns;

}  // namespace

TEST(StrandField, AtRestTheStrandsAreTheirRestShape) {
  Bound b = bindSphere(1500, 800);
  std::vector<glm::vec3> out;
  b.field.deform(b.solver.particles().position, b.solver.particles().direction, nullptr, out);
  ASSERT_EQ(out.size(), b.field.rest().points.size());
  float worst = 0;
  for (std::size_t q = 0; q < out.size(); ++q) worst = std::max(worst, glm::length(out[q] - b.field.rest().points[q]));
  EXPECT_LT(worst, 1e-5f);
}

TEST(StrandField, ARigidMotionOfAllParticlesMovesEveryStrandPointByIt) {
  Bound b = bindSphere(1500, 800);
  // deform a hung state (not the rest one), then move it rigidly
  for (int k = 0; k < 30; ++k) b.solver.step();
  const Particles& p = b.solver.particles();
  std::vector<glm::vec3> before;
  b.field.deform(p.position, p.direction, nullptr, before);
  const glm::mat3 rot(glm::rotate(glm::mat4(1.0f), glm::radians(130.0f), glm::normalize(glm::vec3(0.3f, 1.0f, -0.6f))));
  const glm::vec3 shift(0.7f, -0.4f, 1.1f);
  std::vector<glm::vec3> x(p.size()), t(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    x[i] = rot * p.position[i] + shift;
    t[i] = rot * p.direction[i];
  }
  std::vector<glm::vec3> after;
  b.field.deform(x, t, nullptr, after);
  float worst = 0;
  for (std::size_t q = 0; q < after.size(); ++q)
    worst = std::max(worst, glm::length(after[q] - (rot * before[q] + shift)));
  // float rounding at about a metre from the origin
  EXPECT_LT(worst, 2e-6f);
}

TEST(StrandField, HeadShakeKeepsLengthsSmoothnessAndTheHeadOut) {
  Bound b = bindSphere(2000, 1500, R"({"type": "shake", "amplitude_deg": 40, "frequency_hz": 1.5})");
  std::vector<glm::vec3> out;
  std::vector<float> phi;
  float worst_len = 0, min_phi = INFINITY;
  std::vector<float> turns;
  const int substeps = b.build.substeps;
  for (int frame = 1; frame <= 30; ++frame) {
    for (int k = 0; k < substeps; ++k) b.solver.step();
    if (frame % 5) continue;
    b.field.deform(b.solver, out, 2);
    worst_len = std::max(worst_len, strandLengthError(b.field, out));
    extraTurns(b.field, out, turns);
    b.solver.bodyDistance(out, b.solver.time(), phi);
    const StrandSet& r = b.field.rest();
    for (std::size_t s = 0; s < r.size(); ++s)
      for (std::uint32_t q = r.first[s] + 1; q < r.first[s + 1]; ++q) min_phi = std::min(min_phi, phi[q]);
  }
  std::sort(turns.begin(), turns.end());
  const float p99 = turns[turns.size() * 99 / 100], p999 = turns[turns.size() * 999 / 1000];
  std::printf("strands: worst length error %.4f, extra turn p99 %.1f p99.9 %.1f deg, min distance %.2e m\n",
              worst_len, p99, p999, min_phi);
  EXPECT_LT(worst_len, 0.02f);
  EXPECT_GE(min_phi, 0.0f);
  // smooth: the bends a strand gets from the field, beyond its own
  EXPECT_LT(p99, 30.0f);
  EXPECT_LT(p999, 60.0f);
}

TEST(StrandField, SameBitsForAnyThreadCount) {
  Bound b = bindSphere(1500, 700, R"({"type": "shake", "amplitude_deg": 30, "frequency_hz": 1})");
  for (int k = 0; k < 40; ++k) b.solver.step();
  std::vector<glm::vec3> one, three;
  b.field.deform(b.solver, one, 1);
  b.field.deform(b.solver, three, 3);
  ASSERT_EQ(one.size(), three.size());
  EXPECT_EQ(0, std::memcmp(one.data(), three.data(), one.size() * sizeof(glm::vec3)));
}

TEST(StrandField, RenderStrandsAboveThePointLimitAreRefusedBeforeTheyAreMade) {
  SceneDesc scene = lhtest::sphereScene(1500, "{}", R"({"type": "still"})");
  const HeadModel model = HeadModel::build(scene, scene.source, scene.limits.mesh);
  RenderStrandOptions opt;
  opt.strands = 800;
  opt.points = 24;
  EXPECT_EQ(growRenderStrands(scene, model, opt).size(), 800u);
  // 2 million strands of 256 points (what the command line allows) would
  // take tens of gigabytes: refused by the scene's limit, naming the options
  opt.strands = 2'000'000;
  opt.points = 256;
  try {
    (void)growRenderStrands(scene, model, opt);
    FAIL() << "half a billion strand points were made";
  } catch (const SceneError& e) {
    const std::string what = e.what();
    for (const char* part : {"512000000 points", "limit of", "--strands", "--strand-points", "--allow-expensive"})
      EXPECT_NE(what.find(part), std::string::npos) << part << " in: " << what;
  }
  // the limit is the scene's: lowered, it refuses the small set too
  scene.limits.max_strand_points = 800 * 24 - 1;
  opt.strands = 800;
  opt.points = 24;
  EXPECT_THROW((void)growRenderStrands(scene, model, opt), SceneError);
}
