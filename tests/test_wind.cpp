// Wind as SPH air (SPEC §5): the hair-air drag is equal and opposite, air
// forces conserve momentum, still air stays still in its open box, and a
// steady wind crosses the box at its speed.
#include "air.hpp"
#include "random.hpp"
#include "test_support.hpp"

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
  air.findNeighbors(hx, 2);
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
  ASSERT_GT(air.size(), 500u);
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
  air.findNeighbors(hx, 2);
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
  const std::size_t n0 = air.size();
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
  mean_speed /= static_cast<double>(air.size());
  // The jittered lattice relaxes with small velocities (SPH noise, a few
  // percent of the sound speed); nothing streams in or out of the faces.
  EXPECT_LT(mean_speed, 0.1 * air.soundSpeed());
  EXPECT_LT(glm::length(drift) / static_cast<double>(air.size()), 0.01);
  EXPECT_NEAR(static_cast<double>(air.size()) / static_cast<double>(n0), 1.0, 0.02);
}

TEST(Wind, SteadyWindCrossesTheBoxAtItsSpeed) {
  AirSystem air(smallBox(2.0f));
  air.fill(0.0, HeadKinematics{}, {});
  const std::size_t n0 = air.size();
  std::vector<glm::vec3> none;
  std::vector<float> nm;
  std::vector<std::uint8_t> nr;
  double t = 0;
  const float dt = static_cast<float>(air.stableTimeStep());
  while (t < 0.5) stepAir(air, t, dt, none, none, nm, nr, none);
  double along = 0;
  for (const auto& v : air.velocities()) along += v.x;
  along /= static_cast<double>(air.size());
  EXPECT_NEAR(along, 2.0, 0.2);
  EXPECT_GT(air.emitted(), n0) << "air keeps coming in upwind";
  EXPECT_GT(air.removed(), n0 / 2) << "and leaving downwind";
  EXPECT_NEAR(static_cast<double>(air.size()) / static_cast<double>(n0), 1.0, 0.08);
}

TEST(Wind, BadWindParametersAreNamed) {
  WindParams w;
  w.spacing = -1;
  w.direction = glm::vec3(0);
  const auto problems = validate(w);
  ASSERT_GE(problems.size(), 2u);
  bool spacing = false, direction = false;
  for (const auto& p : problems) {
    spacing |= p.find("wind.spacing = -1") != std::string::npos;
    direction |= p.find("wind.direction") != std::string::npos;
  }
  EXPECT_TRUE(spacing);
  EXPECT_TRUE(direction);
  EXPECT_THROW(AirSystem{w}, std::invalid_argument);
}
