// Strands carried by the particle field (loosehair/strand_field.hpp): rigid
// motions carry them rigidly, lengths stay within the tolerance, no point
// ends inside a body, strands stay smooth, same bits for any thread count.
#include "test_support.hpp"

#include "loosehair/head_model.hpp"
#include "loosehair/render_strands.hpp"
#include "loosehair/strand_field.hpp"
#include "strands/particle_rotation.hpp"

#include <Eigen/LU>
#include <Eigen/SVD>
#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <algorithm>
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

using lhtest::extraTurns;
using lhtest::strandLengthError;

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
  std::printf("strands: worst length error %.4f, extra turn p99 %.1f p99.9 %.1f deg, min distance %.2e m\n", worst_len,
              p99, p999, min_phi);
  EXPECT_LT(worst_len, 0.02f);
  EXPECT_GE(min_phi, 0.0f);
  // smooth: the bends a strand gets from the field, beyond its own
  EXPECT_LT(p99, 30.0f);
  EXPECT_LT(p999, 60.0f);
}

TEST(StrandField, StrandsEndingInsideAThinPartStayOnTheSideTheyCameFrom) {
  // A plate 3 cm thick where the hanging hair ends (as an ear is to the
  // hair beside it): tips past its middle are nearest to its far side, but
  // pushed there a strand would reach through the plate.
  Bound b = bindSphere(1500, 800);
  for (int k = 0; k < 30; ++k) b.solver.step();
  const Particles& p = b.solver.particles();
  std::vector<glm::vec3> free;
  b.field.deform(p.position, p.direction, nullptr, free, 2);
  const StrandSet& r = b.field.rest();
  // the plate's middle at the 20th percentile of the tips' heights
  std::vector<float> tips;
  for (std::size_t s = 0; s < r.size(); ++s) tips.push_back(free[r.first[s + 1] - 1].y);
  std::sort(tips.begin(), tips.end());
  const float mid = tips[tips.size() / 5], half = 0.015f;
  const BodyContacts plate = [&](std::span<const glm::vec3> pts, float, bool, std::span<float> phi,
                                 std::span<glm::vec3> normal) {
    for (std::size_t k = 0; k < pts.size(); ++k) {
      const float dy = pts[k].y - mid;
      phi[k] = std::abs(dy) - half;
      normal[k] = glm::vec3(0.0f, dy >= 0.0f ? 1.0f : -1.0f, 0.0f);
    }
  };
  std::vector<glm::vec3> out;
  b.field.deform(p.position, p.direction, &plate, out, 2);
  float deepest = INFINITY, lowest = INFINITY;
  std::size_t ending_inside = 0;
  for (std::size_t s = 0; s < r.size(); ++s) {
    // strands that come from above and end in the plate's lower half
    const float tip = free[r.first[s + 1] - 1].y;
    if (!(tip < mid && tip > mid - half)) continue;
    ++ending_inside;
    for (std::uint32_t q = r.first[s]; q < r.first[s + 1]; ++q) {
      deepest = std::min(deepest, std::abs(out[q].y - mid) - half);
      lowest = std::min(lowest, out[q].y - (mid + half));
    }
  }
  EXPECT_GT(ending_inside, 20u) << "the plate must hold tips in its lower half";
  EXPECT_GE(deepest, 0.0f) << "a point was left inside the plate";
  EXPECT_GE(lowest, 0.0f) << "a strand from above was pushed through to the plate's far side";
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
  const StrandSet serial = growRenderStrands(scene, model, opt);
  EXPECT_EQ(serial.size(), 800u);
  // grown on three threads: the same strands
  const StrandSet threaded = growRenderStrands(scene, model, opt, 3);
  ASSERT_EQ(serial.points.size(), threaded.points.size());
  EXPECT_EQ(serial.first, threaded.first);
  EXPECT_EQ(0, std::memcmp(serial.points.data(), threaded.points.data(), serial.points.size() * sizeof(glm::vec3)));
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

TEST(ParticleRotation, AnIllConditionedNeighbourhoodGetsTheNearestRotation) {
  // A neighbourhood's A from the bundled hang (its hair turned from up to
  // down and forward), where the iteration from the hair direction was
  // still turning by 3e-3 rad a step at its cap. The answer must be the
  // rotation nearest A (its polar rotation, here by Eigen's SVD in double)
  // and turn with the neighbourhood.
  const glm::mat3 a(glm::vec3(0.00174607604f, 0.00113652635f, -0.000357867655f),
                    glm::vec3(-0.00114054303f, -0.00250005443f, 0.000190997554f),
                    glm::vec3(0.000626210414f, 0.00605706358f, 0.00208747969f));
  const glm::vec3 rest_dir = glm::normalize(glm::vec3(-3.17955141e-06f, 1.0f, -1.27182057e-05f));
  const glm::vec3 dir = glm::normalize(glm::vec3(-0.339125752f, -0.544433653f, 0.767193437f));
  Eigen::Matrix3d m;
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) m(r, c) = a[c][r];
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(m, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d u = svd.matrixU();
  if ((u * svd.matrixV().transpose()).determinant() < 0.0) u.col(2) *= -1.0;
  const Eigen::Matrix3d polar = u * svd.matrixV().transpose();
  const glm::mat3 r = rotationPart(a, rest_dir, dir);
  double err = 0.0;
  for (int c = 0; c < 3; ++c)
    for (int k = 0; k < 3; ++k) err = std::max(err, std::abs(static_cast<double>(r[c][k]) - polar(k, c)));
  EXPECT_LT(err, 1e-4);
  const glm::mat3 g(glm::rotate(glm::mat4(1.0f), glm::radians(130.0f), glm::normalize(glm::vec3(0.3f, 1.0f, -0.6f))));
  const glm::mat3 turned = rotationPart(g * a, rest_dir, g * dir);
  float diff = 0.0f;
  for (int c = 0; c < 3; ++c) diff = std::max(diff, glm::length(turned[c] - (g * r)[c]));
  EXPECT_LT(diff, 1e-4f);
}

// The bodies handed to another thread (the viewer's strand carrier) answer
// as the solver itself does: the head and a torso that has moved in the
// head's frame, exact near the skin, with the same bits.
TEST(StrandField, PlacedBodiesAnswerAsTheSolverDoes) {
  SceneDesc scene = loadScene(lhtest::sourceDir() + "/data/scenes/head-shake.json");
  scene.hair.particles = 800;
  scene.settle = 0.0;
  BuildReport build;
  Solver solver = buildSolver(scene, &build);
  solver.advance(20 * build.substeps);  // the head has turned: the torso moved in its frame
  const std::vector<BodyPlacement> placed = solver.bodyPlacements();
  ASSERT_EQ(placed.size(), 2u) << "the head, then the torso";
  EXPECT_NE(placed[1].m, glm::mat3(1.0f));
  const BodyContacts contacts = placedBodyContacts(placed);
  // points around the particles, some inside the bodies
  std::vector<glm::vec3> pts;
  for (std::size_t i = 0; i < solver.particles().size(); i += 3)
    for (float dy : {-0.01f, 0.0f, 0.01f}) pts.push_back(solver.particles().position[i] + glm::vec3(0.0f, dy, 0.004f));
  const float limit = 0.01f;
  std::vector<float> phi_a(pts.size()), phi_b(pts.size());
  std::vector<glm::vec3> n_a(pts.size()), n_b(pts.size());
  contacts(pts, limit, false, phi_a, n_a);
  solver.bodyContacts(pts, solver.time(), limit, phi_b, n_b);
  std::size_t near = 0, inside = 0;
  for (std::size_t k = 0; k < pts.size(); ++k) {
    if (!(phi_b[k] < limit)) {
      EXPECT_GE(phi_a[k], limit) << k;
      continue;
    }
    ++near;
    inside += phi_b[k] < 0.0f;
    EXPECT_EQ(phi_a[k], phi_b[k]) << k;
    EXPECT_EQ(n_a[k], n_b[k]) << k;
  }
  EXPECT_GT(near, 100u);
  EXPECT_GT(inside, 0u);
}
