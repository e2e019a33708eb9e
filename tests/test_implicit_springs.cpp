// Implicit springs (issue "real time at scale", sim/src/solver/implicit_springs.hpp):
// stable far beyond the explicit step's limit, the same step as the
// explicit one where both are accurate, a converged solve, and the same
// bits on any thread count.
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace loosehair;

namespace {

SceneDesc tiny(bool implicit, int substeps, int threads = 2) {
  SceneDesc scene = loadScene(lhtest::sourceDir() + "/tests/data/tiny.json");
  scene.sim.implicit_springs = implicit;
  scene.sim.threads = threads;
  scene.substeps = substeps;
  return scene;
}

// Steps `steps` times; false as soon as the state is not finite (or the
// solver says it became unstable).
bool runFinite(Solver& s, int steps) {
  try {
    for (int k = 0; k < steps; ++k) s.step();
  } catch (const SimulationError&) {
    return false;
  }
  return lhtest::allFinite(s);
}

}  // namespace

TEST(ImplicitSprings, StableAtStepsFarBeyondTheExplicitLimit) {
  // stiff hair, three steps a frame: several times the explicit stable step
  SceneDesc stiff = tiny(false, 60);
  stiff.sim.youngs_modulus = 2e5f;
  const double stable = buildSolver(stiff).initReport().stable_time_step;
  const double dt = 1.0 / 30.0 / 3;
  ASSERT_GT(dt, 3.0 * stable) << "the test needs a step well beyond the explicit limit";
  SceneDesc explicit_scene = stiff;
  explicit_scene.substeps = 3;
  explicit_scene.sim.strain_limit = false;  // the bare integrators, side by side
  explicit_scene.sim.tether = false;
  SceneDesc implicit_scene = explicit_scene;
  implicit_scene.sim.implicit_springs = true;
  Solver ex = buildSolver(explicit_scene);
  Solver im = buildSolver(implicit_scene);
  const int steps = 2 * 30 * 3;  // 2 s, through the shake
  const bool ex_finite = runFinite(ex, steps);
  ASSERT_TRUE(runFinite(im, steps)) << "the implicit springs blew up at dt = " << dt;
  // without the tether and the strain limit the springs alone hold the hair
  const float stretch = lhtest::maxStretch(im, 0.2f);
  std::printf("dt %.1f ms = %.1fx the explicit limit: explicit %s, implicit stretch %.4f\n", dt * 1e3, dt / stable,
              ex_finite ? "finite" : "blew up", stretch);
  EXPECT_FALSE(ex_finite && lhtest::maxStretch(ex, 0.2f) < 0.1f) << "the explicit step should fail here";
  EXPECT_LT(stretch, 0.1f);
}

TEST(ImplicitSprings, AgreesWithTheExplicitStepWhereBothAreAccurate) {
  // a step far below the explicit limit: the linearised backward step and
  // symplectic Euler differ by O(dt^2) per step
  Solver ex = buildSolver(tiny(false, 200));
  Solver im = buildSolver(tiny(true, 200));
  const std::vector<glm::vec3> x0 = ex.particles().position;
  for (int k = 0; k < 100; ++k) {
    ex.step();
    im.step();
  }
  const auto& a = ex.particles().position;
  const auto& b = im.particles().position;
  const auto& s = ex.particles().arc_length;
  double moved = 0, differ = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (ex.particles().is_root[i] || s[i] <= 0) continue;
    moved = std::max(moved, static_cast<double>(glm::length(a[i] - x0[i])));
    differ = std::max(differ, static_cast<double>(glm::length(a[i] - b[i])));
  }
  std::printf("after 100 steps of 0.17 ms: moved up to %.2e m, explicit and implicit differ by %.2e m\n", moved,
              differ);
  ASSERT_GT(moved, 1e-3);
  EXPECT_LT(differ, 0.02 * moved);
}

TEST(ImplicitSprings, TheSolveConvergesToItsTolerance) {
  SceneDesc scene = tiny(true, 3);
  scene.sim.youngs_modulus = 2e5f;
  scene.sim.implicit_tolerance = 1e-6f;
  scene.sim.implicit_iterations = 500;
  Solver s = buildSolver(scene);
  for (int k = 0; k < 20; ++k) {
    s.step();
    ASSERT_LE(s.stats().spring_residual, 1e-6f) << "step " << k;
    ASSERT_LT(s.stats().spring_iterations, 500) << "step " << k;
  }
  std::printf("last step: %d iterations to a relative residual of %.1e\n", s.stats().spring_iterations,
              static_cast<double>(s.stats().spring_residual));
}

TEST(ImplicitSprings, SameBitsForAnyThreadCount) {
  Solver one = buildSolver(tiny(true, 3, 1));
  Solver two = buildSolver(tiny(true, 3, 2));
  Solver three = buildSolver(tiny(true, 3, 3));
  for (int k = 0; k < 90; ++k) {
    one.step();
    two.step();
    three.step();
  }
  EXPECT_EQ(one.stateHash(), two.stateHash());
  EXPECT_EQ(one.stateHash(), three.stateHash());
  Solver ex = buildSolver(tiny(false, 3, 2));
  for (int k = 0; k < 90; ++k) (void)runFinite(ex, 1);
  EXPECT_NE(one.stateHash(), ex.stateHash()) << "the switch changes the integrator";
}
