// Wind as SPH air (method.md §5): the hair-air drag is equal and opposite, air
// forces conserve momentum, still air stays still in its open box, and a
// steady wind crosses the box at its speed.
#include "wind/air.hpp"
#include "util/random.hpp"
#include "test_support.hpp"
#include "loosehair/scene.hpp"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

using namespace loosehair;

namespace {

WindParams smallBox(float speed) {
  WindParams w;
  w.direction = glm::vec3(1, 0, 0);
  w.speed = speed;
  w.box_center = glm::vec3(0);
  w.box_size = glm::vec3(0.4f, 0.3f, 0.3f);
  w.spacing = 0.03f;
  return w;
}

void stepAir(AirSystem& air, double& t, float dt, std::span<const glm::vec3> hx, std::span<const glm::vec3> hv,
             std::span<const float> hm, std::span<const std::uint8_t> root, std::vector<glm::vec3>& hf) {
  const HeadKinematics still;
  air.findNeighbors(hx, dt, 2);
  std::fill(hf.begin(), hf.end(), glm::vec3(0));
  air.accumulateForces(hx, hv, hm, root, hf, dt, 2);
  air.integrate(t, dt, still, 2);
  t += dt;
  air.emitAndRemove(t, dt, still, {});
}

}  // namespace

TEST(Wind, HairAirDragIsEqualAndOppositeAndAirForcesConserveMomentum) {
  AirSystem air(smallBox(3.0f));
  air.fill(0.0, HeadKinematics{}, {});
  ASSERT_GT(air.count(), 500u);
  Random rng(5);
  const std::size_t nh = 400;
  std::vector<glm::vec3> hx(nh), hv(nh), hf(nh, glm::vec3(0));
  std::vector<float> hm(nh, 1e-5f);
  std::vector<std::uint8_t> root(nh, 0);
  for (std::size_t i = 0; i < nh; ++i) {
    hx[i] = glm::vec3(rng.uniform(-0.05, 0.05), rng.uniform(-0.05, 0.05), rng.uniform(-0.05, 0.05));
    hv[i] = glm::vec3(rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5), 0.0f);
  }
  root[7] = 1;  // roots feel nothing and give nothing
  air.findNeighbors(hx, 0.01f, 2);
  ASSERT_GT(air.hairAirPairs(), 1000u);
  // A large step: the limiter must engage and keep the pairs symmetric.
  air.accumulateForces(hx, hv, hm, root, hf, 0.01f, 2);
  glm::dvec3 hair_sum(0), drag_sum(0), total(0);
  double scale = 0;
  for (const auto& f : hf) {
    hair_sum += glm::dvec3(f);
    scale += glm::length(glm::dvec3(f));
  }
  for (const auto& f : air.airDragForce()) drag_sum += glm::dvec3(f);
  for (const auto& f : air.airForce()) {
    total += glm::dvec3(f);
    scale += glm::length(glm::dvec3(f));
  }
  EXPECT_EQ(hf[7], glm::vec3(0));
  ASSERT_GT(scale, 0.0);
  EXPECT_LT(glm::length(hair_sum + drag_sum), 1e-6 * scale) << "drag on hair = - drag on air";
  EXPECT_LT(glm::length(hair_sum + total), 1e-5 * scale) << "pressure and viscosity are pair forces";
  // And the drag pulls the hair towards the air's velocity (3 m/s along x).
  double along = 0;
  for (std::size_t i = 0; i < nh; ++i) along += glm::dot(hf[i], glm::vec3(1, 0, 0));
  EXPECT_GT(along, 0.0);
}

TEST(Wind, StillAirStaysStillInItsOpenBox) {
  AirSystem air(smallBox(0.0f));
  air.fill(0.0, HeadKinematics{}, {});
  const std::size_t n0 = air.count();
  std::vector<glm::vec3> none;
  std::vector<float> nm;
  std::vector<std::uint8_t> nr;
  double t = 0;
  const float dt = 0.5f * static_cast<float>(std::min(air.stableTimeStep(), 1e-3));
  double mean_speed = 0;
  glm::dvec3 drift(0);
  for (int k = 0; k < 400; ++k) stepAir(air, t, dt, none, none, nm, nr, none);
  for (const auto& v : air.velocities()) {
    mean_speed += glm::length(v);
    drift += glm::dvec3(v);
  }
  mean_speed /= static_cast<double>(air.count());
  // The jittered lattice relaxes with small velocities (SPH noise, a few
  // percent of the sound speed); nothing streams in or out of the faces.
  EXPECT_LT(mean_speed, 0.1 * air.soundSpeed());
  EXPECT_LT(glm::length(drift) / static_cast<double>(air.count()), 0.01);
  EXPECT_NEAR(static_cast<double>(air.count()) / static_cast<double>(n0), 1.0, 0.02);
}

TEST(Wind, SteadyWindCrossesTheBoxAtItsSpeed) {
  AirSystem air(smallBox(2.0f));
  air.fill(0.0, HeadKinematics{}, {});
  const std::size_t n0 = air.count();
  std::vector<glm::vec3> none;
  std::vector<float> nm;
  std::vector<std::uint8_t> nr;
  double t = 0;
  const float dt = static_cast<float>(air.stableTimeStep());
  while (t < 0.5) stepAir(air, t, dt, none, none, nm, nr, none);
  double along = 0;
  for (const auto& v : air.velocities()) along += v.x;
  along /= static_cast<double>(air.count());
  EXPECT_NEAR(along, 2.0, 0.2);
  EXPECT_GT(air.emitted(), n0) << "air keeps coming in upwind";
  EXPECT_GT(air.removed(), n0 / 2) << "and leaving downwind";
  EXPECT_NEAR(static_cast<double>(air.count()) / static_cast<double>(n0), 1.0, 0.08);
}

// The density projection (sim/src/wind/air_projection.cpp): squeezed air
// spreads back towards rest density within a step, and the velocity takes
// the shift over the step; the shifts are pairs', equal and opposite, so the
// air's momentum is kept.
TEST(Wind, ProjectionSpreadsSqueezedAirByPairShifts) {
  WindParams w = smallBox(0.0f);
  ASSERT_GT(w.projection_iterations, 0) << "projected air is the default";
  w.sound_speed = 20.0f;
  w.box_size = glm::vec3(0.6f, 0.4f, 0.4f);
  AirSystem air(w);
  air.fill(0.0, HeadKinematics{}, {});
  // squeezed by up to 15% towards the box's centre plane
  for (glm::vec3& x : air.positions()) x.x *= 0.85f + 0.15f * std::min(1.0f, std::abs(x.x) / 0.1f);
  // the squeezed air, a kernel support from the faces (the air nearer a
  // face takes no constraint of its own)
  const float from_face = 0.5f * w.box_size.y - 2.0f * w.spacing * w.h_scale;
  auto worst = [&](const AirSystem& a) {
    double e = 0;
    for (std::size_t q = 0; q < a.count(); ++q) {
      const glm::vec3 x = a.positions()[q];
      if (std::abs(x.x) < 0.1f && std::abs(x.y) < from_face && std::abs(x.z) < from_face)
        e = std::max(e, std::abs(static_cast<double>(a.density()[q]) / a.restDensity() - 1.0));
    }
    return e;
  };
  WindParams w0 = w;
  w0.projection_iterations = 0;
  AirSystem unprojected(w0);
  unprojected.fill(0.0, HeadKinematics{}, {});
  unprojected.positions() = air.positions();
  unprojected.velocities() = air.velocities();
  std::vector<glm::vec3> none;
  const float dt = 0.01f;
  unprojected.findNeighbors(none, dt, 2);
  const double squeezed = worst(unprojected);
  air.findNeighbors(none, dt, 2);
  const double projected = worst(air);
  std::printf("largest density error of squeezed air %.3f, after one step's projection %.3f\n", squeezed, projected);
  EXPECT_GT(squeezed, 0.2);
  EXPECT_LT(projected, 0.5 * squeezed);
  // The air was at rest: its velocities are the shifts over dt.
  glm::dvec3 momentum(0);
  double moved = 0;
  for (const glm::vec3& v : air.velocities()) {
    momentum += glm::dvec3(v);
    moved += glm::length(glm::dvec3(v));
  }
  std::printf("momentum gained %.2e of the %.3f moved\n", glm::length(momentum), moved);
  ASSERT_GT(moved, 0.05 * static_cast<double>(air.count())) << "m/s: the squeeze moves the air";
  EXPECT_LT(glm::length(momentum), 1e-4 * moved) << "pair shifts keep the momentum";
}

TEST(Wind, BadWindParametersAreNamed) {
  WindParams w;
  w.spacing = -1;
  w.direction = glm::vec3(0);
  w.projection_iterations = -2;
  const auto problems = validate(w);
  ASSERT_GE(problems.size(), 2u);
  bool spacing = false, direction = false, rounds = false;
  for (const auto& p : problems) {
    rounds |= p.find("wind.projection_iterations = -2") != std::string::npos;
    spacing |= p.find("wind.spacing = -1") != std::string::npos;
    direction |= p.find("wind.direction") != std::string::npos;
  }
  EXPECT_TRUE(spacing);
  EXPECT_TRUE(direction);
  EXPECT_TRUE(rounds);
  EXPECT_THROW(AirSystem{w}, std::invalid_argument);
}

TEST(Wind, ABoxThatCannotReachTheHairIsWarnedOf) {
  // the sphere scene's hair hangs around the origin (a 10 cm head)
  auto build = [](glm::vec3 centre, glm::vec3 size, AirModel model) {
    SceneDesc scene = lhtest::sphereScene(400);
    scene.has_wind = true;
    scene.wind.model = model;
    scene.wind.box_center = centre;
    scene.wind.box_size = size;
    BuildReport report;
    (void)buildSolver(scene, &report);
    std::string all;
    for (const std::string& w : report.warnings) all += w + "\n";
    return all;
  };
  for (AirModel model : {AirModel::Grid, AirModel::Particles}) {
    const std::string around = build({0.0f, -0.1f, 0.0f}, {0.6f, 0.6f, 0.6f}, model);
    EXPECT_EQ(around.find("wind.box"), std::string::npos) << around;
    const std::string far = build({5.0f, 5.0f, 5.0f}, {0.6f, 0.6f, 0.6f}, model);
    EXPECT_NE(far.find("holds none of the hair"), std::string::npos) << far;
    EXPECT_NE(far.find("wind.box_center [5, 5, 5]"), std::string::npos) << far;
    // a box inside the head holds no air at all
    const std::string inside = build({0.0f, 0.0f, 0.0f}, {0.05f, 0.05f, 0.05f}, model);
    EXPECT_NE(inside.find("holds no air"), std::string::npos) << inside;
  }
}
