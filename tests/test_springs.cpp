// method.md §3.2-3.3 and §4: loose springs with constant tensile modulus, pair
// forces that conserve momentum, no force from rigid motion, and hair
// directions that turn with the hair.
#include "solver/kernel.hpp"
#include "util/random.hpp"
#include "test_support.hpp"

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

using namespace loosehair;

namespace {

float median(std::vector<float> v) {
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

float percentile(std::vector<float> v, double q) {
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1))];
}

// Raw root-side sum of l k over its rest value: how much the springs
// loosened before rescaling.
std::vector<float> rawLooseness(const Solver& s, std::vector<std::uint8_t>& select) {
  const CubicKernel k1(s.params().h1);
  const auto& c = s.connections();
  const auto& x = s.particles().position;
  std::vector<float> out;
  select.assign(x.size(), 0);
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (s.particles().is_root[i]) continue;
    double now = 0, rest = 0;
    int slack = 0, active = 0;
    for (std::uint32_t e = c.begin(i); e < c.end(i); ++e) {
      if (c.tip_side[e]) continue;
      const float r = glm::length(x[c.partner[e]] - x[i]);
      now += c.rest_length[e] * c.strength[e] * k1.W(r);
      rest += c.rest_length[e] * c.strength[e] * k1.W(c.rest_length[e]);
      (r >= k1.support() ? slack : active) += 1;
    }
    if (slack > 0 && active > 0) {
      select[i] = 1;
      out.push_back(static_cast<float>(now / rest));
    }
  }
  return out;
}

}  // namespace

TEST(Springs, TensileModulusIsKeptWhileHairMovesAndLoosens) {
  // T_i = (1/A_i) sum_{j in Nr(i)} l_ij alpha_ij k_ij (method.md §3.2). The pair
  // factor alpha_ij averages the factors of i and j (eq. 14), so T_i is E up
  // to the spread of neighbouring factors; what the rescaling guarantees is
  // that each particle keeps its T_i while its springs loosen.
  const auto scene = lhtest::sphereScene(1500, R"({"stiffness_clamp": 50, "youngs_modulus": 5e4})",
                                         R"({"type": "shake", "amplitude_deg": 50, "frequency_hz": 1.5, "cycles": 3})");
  Solver solver = buildSolver(scene);
  const float young = solver.params().youngs_modulus;
  const auto rest = solver.tensileModulus(Side::Root);
  std::vector<float> rest_over_e;
  for (std::size_t i = 0; i < rest.size(); ++i)
    if (!solver.particles().is_root[i] && rest[i] > 0.0f) rest_over_e.push_back(rest[i] / young);
  EXPECT_NEAR(median(rest_over_e), 1.0f, 0.05f);

  auto keptRatio = [&](const std::vector<std::uint8_t>& select) {
    const auto now = solver.tensileModulus(Side::Root);
    std::vector<float> err;
    for (std::size_t i = 0; i < now.size(); ++i)
      if (select[i] && rest[i] > 0.0f) err.push_back(std::abs(now[i] / rest[i] - 1.0f));
    return err;
  };
  std::vector<std::uint8_t> hair(rest.size());
  for (std::size_t i = 0; i < hair.size(); ++i) hair[i] = solver.particles().is_root[i] ? 0 : 1;

  solver.advance(static_cast<int>(1.0 / solver.params().time_step));  // 1 s of shaking
  const auto moving = keptRatio(hair);
  EXPECT_LT(median(moving), 0.03f);
  EXPECT_LT(percentile(moving, 0.9), 0.15f);

  // Split the hair: move everything in front of the head 4 cm forward, so the
  // connections across the cut go slack.
  auto x = solver.particles().position;
  for (std::size_t i = 0; i < x.size(); ++i)
    if (!solver.particles().is_root[i] && x[i].z > 0.0f) x[i].z += 0.04f;
  solver.setKinematicState(x, solver.particles().velocity, solver.particles().direction);
  std::vector<std::uint8_t> loosened;
  const auto raw = rawLooseness(solver, loosened);
  ASSERT_GT(raw.size(), 20u);
  // (below 0.8 after explicit shaking, 0.803 after implicit: the shaken
  // state differs; the rescaling check below is the point)
  EXPECT_LT(median(raw), 0.85f) << "the cut should have loosened the raw springs";
  const auto after = keptRatio(loosened);
  EXPECT_LT(median(after), 0.1f) << "rescaling keeps the modulus where connections went slack";
}

TEST(Springs, StiffnessClampBoundsTheRescaling) {
  // With the clamp at 1 a side can never stiffen beyond its rest state, so a
  // cut loosens the hair; with a generous clamp the rescaling makes up for it.
  auto cut = [](Solver& solver) {
    auto x = solver.particles().position;
    for (std::size_t i = 0; i < x.size(); ++i)
      if (!solver.particles().is_root[i] && x[i].z > 0.0f) x[i].z += 0.03f;
    solver.setKinematicState(x, solver.particles().velocity, solver.particles().direction);
  };
  Solver stiff = buildSolver(lhtest::sphereScene(800, R"({"stiffness_clamp": 1})"));
  Solver free = buildSolver(lhtest::sphereScene(800, R"({"stiffness_clamp": 1000})"));
  const auto rest = stiff.tensileModulus(Side::Root);
  cut(stiff);
  cut(free);
  std::vector<std::uint8_t> loosened;
  (void)rawLooseness(stiff, loosened);
  const auto clamped = stiff.tensileModulus(Side::Root);
  const auto unclamped = free.tensileModulus(Side::Root);
  std::vector<float> ratio_clamped, ratio_free;
  for (std::size_t i = 0; i < rest.size(); ++i) {
    if (!loosened[i] || !(rest[i] > 0.0f)) continue;
    ratio_clamped.push_back(clamped[i] / rest[i]);
    ratio_free.push_back(unclamped[i] / rest[i]);
  }
  ASSERT_GT(ratio_clamped.size(), 10u);
  EXPECT_LT(median(ratio_clamped), 0.85f);
  EXPECT_GT(median(ratio_free), 0.9f);
}

TEST(Springs, PairForcesSumToZero) {
  const auto scene =
      lhtest::sphereScene(1500, "{}", R"({"type": "shake", "amplitude_deg": 40, "frequency_hz": 2, "cycles": 2})");
  Solver solver = buildSolver(scene);
  solver.advance(150);
  // random relative velocities exercise damping, collision and friction
  Random rng(11);
  auto v = solver.particles().velocity;
  for (auto& vi : v) vi += glm::vec3(rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3));
  solver.setKinematicState(solver.particles().position, v, solver.particles().direction);
  const auto f = solver.internalForces();
  glm::dvec3 sum(0.0);
  double magnitude = 0;
  for (const auto& fi : f) {
    sum += glm::dvec3(fi);
    magnitude += glm::length(glm::dvec3(fi));
  }
  ASSERT_GT(magnitude, 0.0);
  EXPECT_LT(glm::length(sum), 1e-5 * magnitude);
}

TEST(Springs, RigidlyMovedRestStateHasNoInternalForce) {
  // No pressure: the rest state is then force free (springs at rest length,
  // no relative velocity for damping, collision or friction).
  const auto scene = lhtest::sphereScene(1500, R"({"pressure_stiffness": 0})");
  Solver solver = buildSolver(scene);
  const auto& p = solver.particles();
  const glm::mat3 rot(glm::rotate(glm::mat4(1.0f), 0.9f, glm::normalize(glm::vec3(1, 2, -1))));
  const glm::vec3 shift(0.3f, -0.2f, 0.1f);
  std::vector<glm::vec3> x(p.size()), t(p.size()), v(p.size(), glm::vec3(0.0f));
  for (std::size_t i = 0; i < p.size(); ++i) {
    x[i] = rot * p.position[i] + shift;
    t[i] = glm::normalize(rot * p.direction[i]);
  }
  const float area = std::pow(p.mass[0] / solver.params().material_density, 2.0f / 3.0f);
  const float one_percent = solver.params().youngs_modulus * area * 0.01f;  // N

  solver.setKinematicState(x, v, t);
  float worst = 0;
  for (const auto& fi : solver.internalForces()) worst = std::max(worst, glm::length(fi));
  EXPECT_LT(worst, 0.01f * one_percent);

  // The same motion with a 1% stretch does produce forces (the test can fail).
  for (auto& xi : x) xi = shift + 1.01f * (xi - shift);
  solver.setKinematicState(x, v, t);
  worst = 0;
  for (const auto& fi : solver.internalForces()) worst = std::max(worst, glm::length(fi));
  EXPECT_GT(worst, 0.1f * one_percent);
}

TEST(Solver, SetKinematicStateRefreshesNeighboursAndDensity) {
  Solver solver = buildSolver(lhtest::sphereScene(500));
  const auto& p = solver.particles();
  // Spread the hair particles 1 m apart: each is then alone, with only its
  // own contribution m W(0, h2) to the density and no hair-hair force.
  auto x = p.position;
  for (std::size_t i = 0; i < x.size(); ++i)
    if (!p.is_root[i]) x[i] = glm::vec3(static_cast<float>(i), 5.0f, 0.0f);
  solver.setKinematicState(x, p.velocity, p.direction);
  const CubicKernel k2(solver.params().h2);
  const auto rho = solver.density();
  for (std::size_t i = 0; i < x.size(); ++i)
    if (!p.is_root[i]) {
      ASSERT_FLOAT_EQ(rho[i], p.mass[i] * k2.W(0.0f)) << "particle " << i;
    }
}

TEST(Directions, TurnWithARigidRotationOfTheWholeHair) {
  // Without gravity and with the head sphere at the origin the dynamics are
  // rotation invariant: a rotated start gives the rotated result.
  // Tethers pull towards the fixed root points, which a rotated state does
  // not move: they are off here.
  const auto scene =
      lhtest::sphereScene(1000, R"({"gravity": [0, 0, 0], "tether": false})", R"({"type": "still"})", 40);
  Solver a = buildSolver(scene);
  Solver b = buildSolver(scene);
  const glm::mat3 rot(glm::rotate(glm::mat4(1.0f), 1.3f, glm::normalize(glm::vec3(0.3f, 1, 0.5f))));
  Random rng(5);
  const auto& p = a.particles();
  std::vector<glm::vec3> v(p.size()), rx(p.size()), rv(p.size()), rt(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    v[i] = p.is_root[i] ? glm::vec3(0.0f) : glm::vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    rx[i] = rot * p.position[i];
    rv[i] = rot * v[i];
    rt[i] = glm::normalize(rot * p.direction[i]);
  }
  const auto t0 = p.direction;
  a.setKinematicState(p.position, v, p.direction);
  b.setKinematicState(rx, rv, rt);
  a.advance(25);
  b.advance(25);
  float turned = 0, mismatch = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    turned = std::max(turned, std::acos(std::clamp(glm::dot(a.particles().direction[i], t0[i]), -1.0f, 1.0f)));
    mismatch = std::max(mismatch, glm::length(b.particles().direction[i] - rot * a.particles().direction[i]));
  }
  std::printf("turned %.3f rad, mismatch %.5f\n", turned, mismatch);
  EXPECT_GT(turned, 0.05f) << "the directions should have changed";
  // The two runs differ only by rounding, which 25 steps of collisions
  // amplify to about 1e-2; a direction update that ignored the rotation
  // would miss by about |R t - t| ~ 1.
  EXPECT_LT(mismatch, 2e-2f);
}
