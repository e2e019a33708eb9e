// Bundled styles simulated on the bundled head (SPEC §6.2): each holds its
// shape on a still head and still swings when the head shakes; the
// ponytail's tail swings while the hair above the tie stays on the head.
#include "loosehair/groom_import.hpp"
#include "loosehair/head_model.hpp"
#include "loosehair/strand_files.hpp"
#include "loosehair/style.hpp"
#include "scenario_watch.hpp"
#include "test_support.hpp"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

using namespace loosehair;
using lhtest::expectInvariants;
using lhtest::run;
using lhtest::Watch;

namespace {

constexpr int kParticles = 3000;

SceneDesc styled(const std::string& scene, const std::string& style, bool keep_shape = true) {
  SceneDesc s = loadScene(lhtest::sourceDir() + "/data/scenes/" + scene + ".json");
  s.hair.particles = kParticles;
  s.hair.style = lhtest::sourceDir() + "/data/styles/" + style + ".json";
  if (!keep_shape) {
    s.sim.shape_keeping = 0.0f;
    s.shape_keeping_auto = false;
  }
  return s;
}

float longestHair(const Solver& solver) {
  float l = 0;
  for (float s : solver.particles().arc_length) l = std::max(l, s);
  return l;
}

// Distances of the hair particles from their styled positions (head frame).
std::vector<float> shapeErrors(const Solver& solver, const std::vector<glm::vec3>& styled_positions) {
  std::vector<float> e;
  const auto& p = solver.particles();
  for (std::size_t i = 0; i < p.size(); ++i)
    if (!p.is_root[i]) e.push_back(glm::length(p.position[i] - styled_positions[i]));
  std::sort(e.begin(), e.end());
  return e;
}

float quantile(const std::vector<float>& sorted, double q) {
  return sorted[std::min(sorted.size() - 1, static_cast<std::size_t>(q * static_cast<double>(sorted.size())))];
}

struct ShapeFigures {
  float median, p95;
};

ShapeFigures holdStill(const std::string& style, bool keep_shape, Watch* watch = nullptr) {
  Solver solver = buildSolver(styled("hang", style, keep_shape));
  const std::vector<glm::vec3> start = solver.particles().position;
  const Watch w = run(solver, 3.0, longestHair(solver), [] {}, 4);
  if (watch) *watch = w;
  const std::vector<float> e = shapeErrors(solver, start);
  return {quantile(e, 0.5), quantile(e, 0.95)};
}

// The hair that hangs from a tie: its root is the point where its strand
// crosses the ring (none without ties).
std::vector<std::uint8_t> hangingFromTies(const Solver& solver, const Style& style) {
  std::vector<std::uint8_t> beyond;
  if (style.ties.empty()) return beyond;
  const Particles& p = solver.particles();
  beyond.assign(p.size(), 0);
  for (std::size_t i = 0; i < p.size(); ++i)
    for (const HairTie& tie : style.ties)
      if (glm::length(p.root_point[i] - tie.center) <= tie.radius + 1e-4f) beyond[i] = 1;
  return beyond;
}

// Gain and lag as the head-shake scenario measures them (test_head_scenarios),
// of the hair that swings: of a tied style, the hair beyond the ties (the
// hair between scalp and tie is held on the head, as the roots are).
lhtest::GainLag shake(const std::string& style, Watch* watch) {
  const SceneDesc scene = styled("head-shake", style);
  Solver solver = buildSolver(scene);
  std::vector<glm::vec3> start;
  solver.worldPositions(start);
  const float min_arc = std::min(0.12f, 0.5f * longestHair(solver));
  const std::vector<std::uint8_t> swinging = hangingFromTies(solver, loadStyle(scene.hair.style));
  std::vector<double> t, head, hair;
  *watch = run(solver, 3.0, longestHair(solver), [&] {
    t.push_back(solver.time());
    head.push_back(lhtest::headYaw(solver));
    hair.push_back(lhtest::hairYaw(solver, start, min_arc, swinging));
  }, 4);
  return lhtest::fitGainAndLag(t, head, hair, 0.6, 2.5);
}


class BundledStyle : public ::testing::TestWithParam<const char*> {};

}  // namespace

TEST_P(BundledStyle, HoldsItsShapeStillAndSwingsWhenTheHeadShakes) {
  const std::string style = GetParam();
  Watch still;
  const ShapeFigures kept = holdStill(style, true, &still);
  expectInvariants(still, style + " still");
  const ShapeFigures plain = holdStill(style, false);
  Watch moving;
  const lhtest::GainLag gl = shake(style, &moving);
  expectInvariants(moving, style + " shaking");
  std::printf("%s: still 3 s, distance from the styled shape: median %.1f mm, p95 %.1f mm "
              "(without shape keeping %.1f / %.1f mm); head shake: gain %.2f, lag %.0f ms; "
              "stretch %.4f / %.4f, deepest %.1e / %.1e m\n",
              style.c_str(), kept.median * 1e3, kept.p95 * 1e3, plain.median * 1e3, plain.p95 * 1e3, gl.gain,
              gl.lag * 1e3, still.worst_stretch, moving.worst_stretch, still.deepest, moving.deepest);
  EXPECT_LT(kept.median, 0.01f) << style;
  EXPECT_LT(kept.p95, 0.03f) << style;
  EXPECT_GT(plain.median, kept.median) << style << ": shape keeping must make a difference";
  EXPECT_LT(gl.gain, 0.95) << style << ": the hair lags the head";
  EXPECT_GT(gl.lag, 0.05) << style;
}

INSTANTIATE_TEST_SUITE_P(Styles, BundledStyle,
                         ::testing::Values("long-straight", "bob", "side-swept", "swept-back", "wavy", "ponytail"),
                         [](const auto& info) {
                           std::string n = info.param;
                           std::replace(n.begin(), n.end(), '-', '_');
                           return n;
                         });

// A tie holds the hair between scalp and ring on the head (its hold,
// HairTie::hold) while the tail beyond it swings when the head turns.
TEST(StyleScenario, PonytailTailSwingsWhileTheHairAboveTheTieStaysOnTheHead) {
  const SceneDesc scene = styled("head-shake", "ponytail");
  const Style style = loadStyle(scene.hair.style);
  ASSERT_EQ(style.ties.size(), 1u);
  const HairTie& tie = style.ties[0];
  Solver solver = buildSolver(scene);
  const std::vector<glm::vec3> x0 = solver.particles().position;
  const auto& p = solver.particles();
  // beyond the tie: along its axis past the ring; above: the other side
  std::vector<std::size_t> tail, above;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.is_root[i]) continue;
    const float along = glm::dot(x0[i] - tie.center, tie.axis);
    if (along > tie.width + 0.02f) tail.push_back(i);
    else if (along < -tie.width) above.push_back(i);
  }
  ASSERT_GT(tail.size(), 200u);
  ASSERT_GT(above.size(), 200u);
  auto headDistance = [&](double time) {
    std::vector<glm::vec3> hair;
    for (std::size_t i : above) hair.push_back(solver.particles().position[i]);
    std::vector<float> phi;
    solver.bodyDistance(hair, time, phi);
    return phi;
  };
  const std::vector<float> phi0 = headDistance(solver.time());
  float tail_swing = 0, above_drift = 0;
  const Watch w = run(solver, 3.0, longestHair(solver), [&] {
    const auto& x = solver.particles().position;  // head frame
    double tail_sum = 0;
    for (std::size_t i : tail) tail_sum += glm::length(x[i] - x0[i]);
    tail_swing = std::max(tail_swing, static_cast<float>(tail_sum / static_cast<double>(tail.size())));
    std::vector<float> drift;
    for (std::size_t i : above) drift.push_back(glm::length(x[i] - x0[i]));
    std::sort(drift.begin(), drift.end());
    above_drift = std::max(above_drift, quantile(drift, 0.95));
  });
  expectInvariants(w, "ponytail shaking");
  const std::vector<float> phi = headDistance(solver.time());
  std::vector<float> lifted;
  for (std::size_t k = 0; k < phi.size(); ++k) lifted.push_back(phi[k] - phi0[k]);
  std::sort(lifted.begin(), lifted.end());
  const float above_lifted = quantile(lifted, 0.95);
  std::printf("ponytail: the tail moves %.1f mm on average in the head frame at most, the hair above the tie "
              "%.1f mm (95th percentile), and ends %.1f mm further from the head than styled (95th percentile)\n",
              tail_swing * 1e3, above_drift * 1e3, above_lifted * 1e3);
  EXPECT_GT(tail_swing, 0.03f) << "the tail swings";
  EXPECT_LT(above_drift, 0.015f) << "the hair between scalp and tie stays where it was styled";
  EXPECT_LT(above_lifted, 0.005f) << "and on the head";
}

// A groom made elsewhere, as a user brings one: the wavy style's strands
// written as a .hair file, read back, imported onto the head (one wisp a
// strand), and simulated still and shaking.
TEST(StyleScenario, AnImportedHairGroomSimulatesAndKeepsItsShape) {
  SceneDesc scene = styled("head-shake", "wavy");
  const Style wavy = loadStyle(scene.hair.style);
  const HeadModel head = HeadModel::build(wavy.head, wavy.source);
  const StrandSet strands = buildMemberStrands(wavy, head);
  const auto dir = std::filesystem::temp_directory_path() /
                   ("loosehair-groom-" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()));
  std::filesystem::create_directories(dir);
  const std::string file = (dir / "wavy.hair").string();
  writeStrands(strands, file);
  GroomImportReport rep;
  const Style groom = importGroom(readPolylines(file), wavy.head, head, file, {}, &rep);
  std::filesystem::remove_all(dir);
  EXPECT_EQ(rep.strands_kept, strands.size());
  EXPECT_EQ(groom.wisps.size(), strands.size());
  scene.hair.style.clear();
  scene.hair.style_data = std::make_shared<const Style>(groom);

  SceneDesc still = scene;
  still.motion = HeadTrajectory::still();
  Solver rest = buildSolver(still);
  const std::vector<glm::vec3> start = rest.particles().position;
  const Watch w_still = run(rest, 2.0, longestHair(rest), [] {}, 4);
  expectInvariants(w_still, "imported groom still");
  const std::vector<float> e = shapeErrors(rest, start);
  Solver shaken = buildSolver(scene);
  const Watch w_shake = run(shaken, 2.0, longestHair(shaken), [] {}, 4);
  expectInvariants(w_shake, "imported groom shaking");
  std::printf("imported groom: %zu strands, %zu particles; still 2 s: median %.1f mm, p95 %.1f mm from the "
              "groom\n", groom.wisps.size(), rest.particles().size(), quantile(e, 0.5) * 1e3,
              quantile(e, 0.95) * 1e3);
  EXPECT_LT(quantile(e, 0.5), 0.01f);
  EXPECT_LT(quantile(e, 0.95), 0.03f);
}
