// Shape keeping (method.md §6.2, docs/design.md "Styles and shape keeping") on the
// sphere head: the styled state is at rest, the hold is what keeps it, a
// tie's hold keeps the hair between scalp and ring in place while the tail
// swings, and holds the step cannot integrate are refused.
#include "loosehair/style.hpp"
#include "style_fixtures.hpp"
#include "test_support.hpp"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

using namespace loosehair;
using namespace lhtest::styles;

namespace {

constexpr const char* kShake =
    R"({"type": "shake", "amplitude_deg": 40, "frequency_hz": 1.0, "cycles": 1, "start": 0.1})";

SceneDesc styledSphere(const Style& style, int particles, const std::string& solver_json = "{}",
                       const std::string& motion_json = R"({"type": "still"})") {
  SceneDesc s = lhtest::sphereScene(particles, solver_json, motion_json);
  s.hair.style_data = std::make_shared<const Style>(style);
  return s;
}

// Distances of the hair particles from where they started (head frame), sorted.
std::vector<float> drift(const Solver& solver, const std::vector<glm::vec3>& x0) {
  std::vector<float> d;
  const Particles& p = solver.particles();
  for (std::size_t i = 0; i < p.size(); ++i)
    if (!p.is_root[i]) d.push_back(glm::length(p.position[i] - x0[i]));
  std::sort(d.begin(), d.end());
  return d;
}

float quantile(const std::vector<float>& sorted, double q) {
  return sorted[std::min(sorted.size() - 1, static_cast<std::size_t>(q * static_cast<double>(sorted.size())))];
}

void stepTo(Solver& solver, double t) {
  while (solver.time() < t - 1e-9) solver.step();
}

}  // namespace

TEST(ShapeKeeping, TheStyledStateIsAtRestAndTheHoldIsWhatKeepsIt) {
  const Style style = twoWispStyle();  // shape_keeping 1 Hz by default
  Solver kept = buildSolver(styledSphere(style, 1200));
  Solver plain = buildSolver(styledSphere(style, 1200, R"({"shape_keeping": 0})"));
  ASSERT_EQ(kept.particles().size(), plain.particles().size());
  const std::vector<glm::vec3> x0 = kept.particles().position;
  stepTo(kept, 1.0);
  stepTo(plain, 1.0);
  ASSERT_TRUE(lhtest::allFinite(kept));
  const std::vector<float> d_kept = drift(kept, x0), d_plain = drift(plain, x0);
  std::printf(
      "1 s on a still head: drift median %.3f mm, p99 %.3f mm with shape keeping; "
      "median %.1f mm without\n",
      quantile(d_kept, 0.5) * 1e3, quantile(d_kept, 0.99) * 1e3, quantile(d_plain, 0.5) * 1e3);
  EXPECT_LT(quantile(d_kept, 0.99), 1e-3f) << "the styled state is an equilibrium";
  EXPECT_GT(quantile(d_plain, 0.5), 5e-3f) << "without the hold a styled shape sags";
}

TEST(ShapeKeeping, ATiesHoldKeepsTheHairAboveItWhileTheTailSwings) {
  struct Figures {
    float above, tail;
  };
  auto run = [](float hold) {
    const Style style = tiedStyle(hold);
    const HairTie& tie = style.ties[0];
    Solver solver = buildSolver(styledSphere(style, 1500, "{}", kShake));
    const Particles& p = solver.particles();
    const std::vector<glm::vec3> x0 = p.position;
    std::vector<std::size_t> above, tail;
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (p.is_root[i]) continue;
      const float along = glm::dot(x0[i] - tie.center, tie.axis);
      if (along < -tie.width) above.push_back(i);
      if (along > tie.width + 0.02f) tail.push_back(i);
    }
    EXPECT_GT(above.size(), 100u);
    EXPECT_GT(tail.size(), 100u);
    Figures f{0, 0};
    while (solver.time() < 1.2) {
      solver.step();
      float a = 0, t = 0;
      for (std::size_t i : above) a = std::max(a, glm::length(p.position[i] - x0[i]));
      for (std::size_t i : tail) t = std::max(t, glm::length(p.position[i] - x0[i]));
      f.above = std::max(f.above, a);
      f.tail = std::max(f.tail, t);
    }
    EXPECT_TRUE(lhtest::allFinite(solver));
    return f;
  };
  const Figures held = run(8.0f), loose = run(0.0f);
  std::printf(
      "head turn: the hair above the tie moves at most %.1f mm held at 8 Hz, %.1f mm at the style's "
      "1 Hz; the tail %.1f / %.1f mm\n",
      held.above * 1e3, loose.above * 1e3, held.tail * 1e3, loose.tail * 1e3);
  EXPECT_LT(held.above, 0.5f * loose.above) << "the tie's hold keeps the hair between scalp and ring";
  EXPECT_GT(held.tail, 0.02f) << "while the tail swings";
  EXPECT_GT(held.tail, 3.0f * held.above);
}

TEST(ShapeKeeping, HoldsTheStepCannotIntegrateAreRefused) {
  SimParams p;
  p.time_step = 0.01;
  p.shape_keeping = 10.0f;  // 2 pi 10 Hz 0.01 s = 0.63
  bool named = false;
  for (const std::string& problem : validate(p))
    named = named || problem.find("shape_keeping = 10") != std::string::npos;
  EXPECT_TRUE(named) << "a hold too strong for the step is named";
  p.shape_keeping = 5.0f;  // 0.31
  EXPECT_TRUE(validate(p).empty());

  const Style style = tiedStyle(4.0f);
  {
    Solver off = buildSolver(styledSphere(style, 600, R"({"shape_keeping": 0})"));
    EXPECT_THROW(off.setShapeKeepingStrengths(std::vector<float>(off.particles().size(), 1.0f)), std::logic_error);
  }
  Solver on = buildSolver(styledSphere(style, 600));
  const std::size_t n = on.particles().size();
  EXPECT_THROW(on.setShapeKeepingStrengths(std::vector<float>(n + 1, 1.0f)), std::invalid_argument);
  std::vector<float> hz(n, 1.0f);
  hz[n / 2] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(on.setShapeKeepingStrengths(hz), std::invalid_argument);
  hz[n / 2] = -1.0f;
  EXPECT_THROW(on.setShapeKeepingStrengths(hz), std::invalid_argument);
  hz[n / 2] = 1.0e4f;
  EXPECT_THROW(on.setShapeKeepingStrengths(hz), std::invalid_argument);
  // the tie's 4 Hz hold cannot be integrated at 25 ms steps
  EXPECT_THROW(on.setTimeStep(0.025), std::invalid_argument);

  // a scene whose tie holds too hard for its step: the field is named
  Style hard = tiedStyle(50.0f);
  SceneDesc scene = styledSphere(hard, 600);
  scene.substeps = 8;  // 30 fps: 4.2 ms steps, 2 pi 50 Hz 4.2 ms = 1.3
  try {
    buildSolver(scene);
    ADD_FAILURE() << "a tie's hold too strong for the step was accepted";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("ties[].hold"), std::string::npos) << e.what();
  }
}
