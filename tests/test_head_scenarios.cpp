// The paper's scenarios on the bundled head, torso and scalp (method.md §5, §6.1,
// §8): each runs at least 3 simulated seconds and checks, at the end of every
// step, that nothing is non-finite, inside the head or torso, or stretched.
// These are the slowest tests; they have their own label ("scenario").
#include "back_hair_split.hpp"
#include "scenario_watch.hpp"
#include "test_support.hpp"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>

using namespace loosehair;

namespace {

using lhtest::bundled;
using lhtest::expectInvariants;
using lhtest::kInsideTolerance;
using lhtest::meanOver;
using lhtest::run;
using lhtest::runSplit;
using lhtest::SplitRun;
using lhtest::Watch;

float maxLength(const SceneDesc& s) { return s.hair.length; }  // the length map peaks at 1

}  // namespace

TEST(HeadScenario, HangSettlesOnHeadAndShoulders) {
  const SceneDesc scene = bundled("hang", 2500);
  Solver solver = buildSolver(scene);
  EXPECT_TRUE(solver.worldBodyCount() == 1) << "the torso is a world body";
  const Watch w = run(solver, 3.0, maxLength(scene), [] {});
  expectInvariants(w, "hang");
  // It hangs: long back hair reaches below the chin (y ~ -0.095), and after
  // 3 s it is nearly at rest.
  float lowest = 1, speed = 0;
  for (std::size_t i = 0; i < solver.particles().size(); ++i) {
    lowest = std::min(lowest, solver.particles().position[i].y);
    speed += glm::length(solver.particles().velocity[i]);
  }
  EXPECT_LT(lowest, -0.15f);
  EXPECT_LT(speed / static_cast<float>(solver.particles().size()), 0.05f);
}

TEST(HeadScenario, BackHairSplitsAndMergesAndInteractionsKeepTheWispsApart) {
  const SplitRun on = runSplit(true, 1);
  // The obstacle parts the back hair (0.3-1.5 s) and is gone after 1.5 s.
  const double before = meanOver(on, on.middle, 0.1, 0.3);
  const double split = meanOver(on, on.middle, 1.3, 1.5);
  const double after = meanOver(on, on.middle, 2.6, 3.0);
  std::printf("particles in the parting: before %.0f, split %.0f, merged %.0f\n", before, split, after);
  // The band also counts hair pinched between the obstacle and the nape:
  // with the implicit springs' backward-Euler damping about 20 of ~90
  // particles stay there to 1.5 s (the explicit solver squeezes them out
  // sideways, leaving ~5; docs/design.md "Implicit springs").
  EXPECT_LT(split, 0.3 * before) << "the back hair splits into two wisps";
  EXPECT_GT(after, 0.6 * before) << "and comes back together under gravity";
  // While they fall back together, the wisps pass through each other
  // without hair-hair interactions and less with them. One run's measure
  // counts a dozen particles and moves by 20-40% with any change of the
  // initial state, so four of five samplings must show it, and their mean
  // by 10% (with the spring solve's tolerance at 5e-3 the means were 0.0039
  // and 0.0061 at one time; at 5e-4, which damps less, 0.0045 and 0.0052,
  // every sampling showing it). At the scene's 6000 particles: at 3000 on the mannequin head
  // the difference drowned in that noise (means 0.0065 with, 0.0067
  // without; at 6000 0.0039 and 0.0061, every sampling showing it). The interactions are compared with the
  // hair chain off: the chain, which keeps each particle by the hair of
  // its own part of the scalp, keeps the wisps apart as well (means 0.0073
  // with and 0.0085 without the interactions, chain on), which hid their
  // effect in a sampling or two.
  double cross_on = 0, cross_off = 0, cross_default = 0;
  int shown = 0;
  constexpr int kSeeds = 5;
  for (std::uint64_t seed = 1; seed <= kSeeds; ++seed) {
    const SplitRun with = runSplit(true, seed, 6000, 1, false), without = runSplit(false, seed, 6000, 1, false);
    const double a = meanOver(with, with.cross, 1.5, 3.0), b = meanOver(without, without.cross, 1.5, 3.0);
    std::printf("seed %d: interpenetration while merging %.4f with hair-hair interactions, %.4f without\n",
                static_cast<int>(seed), a, b);
    if (a < b) ++shown;
    cross_on += a / kSeeds;
    cross_off += b / kSeeds;
    if (seed == 1) cross_default = meanOver(on, on.cross, 1.5, 3.0);
  }
  std::printf("mean interpenetration while merging: %.4f with, %.4f without (seed 1 with the chain: %.4f)\n", cross_on,
              cross_off, cross_default);
  EXPECT_GE(shown, kSeeds - 1) << "samplings with less interpenetration with the interactions on";
  EXPECT_LT(cross_on, 0.9 * cross_off);
}

// At the scene's own resolution, through the parting (the obstacle is
// present to 1.5 s): an obstacle that pinched the hair against the nape
// stretched it by 2.2%.
TEST(HeadScenario, BackHairSplitAtFullResolutionKeepsTheStretchBound) {
  const SceneDesc scene = loadScene(lhtest::sourceDir() + "/data/scenes/back-hair-split.json");
  Solver solver = buildSolver(scene);
  const Watch w = run(solver, 1.6, maxLength(scene), [] {});
  expectInvariants(w, "back-hair-split, 6000 particles");
}

TEST(HeadScenario, HeadShakeHairLagsTheHeadWithoutStretchOrPenetration) {
  const SceneDesc scene = bundled("head-shake", 2500);
  Solver solver = buildSolver(scene);
  std::vector<glm::vec3> start;
  solver.worldPositions(start);
  std::vector<double> t, head, hair;
  const Watch w = run(solver, 3.5, maxLength(scene), [&] {
    t.push_back(solver.time());
    head.push_back(lhtest::headYaw(solver));
    hair.push_back(lhtest::hairYaw(solver, start, 0.12f));  // the part near the scalp turns with it
  });
  expectInvariants(w, "head-shake");
  // hair(t) ~ gain head(t) - lag head'(t) over the shake (0.5-2.5 s)
  const auto [gain, lag] = lhtest::fitGainAndLag(t, head, hair, 0.6, 2.5);
  std::printf("hair follows the shaken head with gain %.2f and lag %.0f ms\n", gain, lag * 1e3);
  EXPECT_GT(gain, 0.3) << "the hair turns with the head";
  EXPECT_GT(lag, 0.03) << "the hair's angular motion lags the head's (s)";
  EXPECT_LT(lag, 0.4);
}

TEST(HeadScenario, HeadNodRunsWithoutStretchOrPenetration) {
  const SceneDesc scene = bundled("head-nod", 2000);
  Solver solver = buildSolver(scene);
  const Watch w = run(solver, 3.0, maxLength(scene), [] {});
  expectInvariants(w, "head-nod");
}

TEST(HeadScenario, WindBlowsTheHairDownwindAndTheHairSlowsTheAir) {
  const SceneDesc scene = bundled("wind", 2500);
  Solver solver = buildSolver(scene);
  ASSERT_TRUE(solver.hasWind());
  const glm::vec3 e = glm::normalize(scene.wind.direction);
  const glm::vec3 up = glm::normalize(glm::vec3(0, 1, 0) - e.y * e), side = glm::cross(e, up);
  auto hairAlong = [&] {
    std::vector<glm::vec3> w;
    solver.worldPositions(w);
    double sum = 0;
    for (const auto& p : w) sum += glm::dot(p, e);
    return sum / static_cast<double>(w.size());
  };
  const double start = hairAlong();
  double behind_sum = 0, beside_sum = 0;
  int samples = 0;
  const Watch w = run(solver, 3.0, maxLength(scene), [&] {
    if (solver.time() < 1.0) return;  // let the flow establish itself
    std::vector<glm::vec3> x, v;
    solver.worldAirPositions(x);
    solver.worldAirVelocities(v);
    double behind = 0, beside = 0;
    int nb = 0, ns = 0;
    for (std::size_t a = 0; a < x.size(); ++a) {
      const glm::vec3 q = x[a] - scene.wind.box_center;
      const float al = glm::dot(q, e), u = glm::dot(q, up), s = glm::dot(q, side);
      if (al < 0.15f || u < -0.2f || u > 0.15f) continue;  // downwind of the head, at its height
      if (std::abs(s) < 0.06f) {
        behind += glm::dot(v[a], e);
        ++nb;
      } else if (std::abs(s) > 0.18f) {
        beside += glm::dot(v[a], e);
        ++ns;
      }
    }
    if (nb > 0 && ns > 0) {
      behind_sum += behind / nb;
      beside_sum += beside / ns;
      ++samples;
    }
  });
  expectInvariants(w, "wind");
  const double moved = hairAlong() - start;
  std::printf(
      "hair centre of mass moved %.1f mm downwind; air speed along the wind behind the head %.2f m/s, beside it %.2f "
      "m/s\n",
      moved * 1e3, behind_sum / samples, beside_sum / samples);
  EXPECT_GT(moved, 0.005) << "the hair's centre of mass moves downwind";
  ASSERT_GT(samples, 30);
  EXPECT_LT(behind_sum / samples, 0.5 * beside_sum / samples) << "air behind the hair is slower than beside it";
  EXPECT_GT(beside_sum / samples, 0.5 * scene.wind.speed) << "the wind blows past the head";
}

TEST(HeadScenario, MeshHeadAndWindAreDeterministicAcrossThreadCounts) {
  SceneDesc scene = bundled("wind", 800);
  auto hashAfter = [&](int threads) {
    scene.sim.threads = threads;
    Solver solver = buildSolver(scene);
    solver.advance(40);
    return solver.stateHash();
  };
  EXPECT_EQ(hashAfter(1), hashAfter(2));
  EXPECT_EQ(hashAfter(2), hashAfter(2));
}

TEST(HeadScenario, ResetIntoTheHeadIsResolvedWithoutEjection) {
  SceneDesc scene = bundled("hang", 1500);
  Solver solver = buildSolver(scene);
  solver.advance(30);
  // Reset: every hair particle 2 cm towards the head's centre, at rest, so
  // that many start inside the head.
  auto x = solver.particles().position;
  const auto dir = solver.particles().direction;
  std::vector<glm::vec3> v(x.size(), glm::vec3(0.0f));
  const glm::vec3 centre(0.0f, 0.03f, 0.0f);
  for (std::size_t i = 0; i < x.size(); ++i)
    if (!solver.particles().is_root[i]) x[i] -= 0.02f * glm::normalize(x[i] - centre);
  std::vector<float> phi;
  solver.bodyDistance(x, solver.time(), phi);
  std::size_t inside = 0;
  for (float d : phi) inside += d < 0 ? 1 : 0;
  ASSERT_GT(inside, 100u) << "the reset should put hair inside the head";
  solver.setKinematicState(x, v, dir);
  solver.step();
  const auto& p = solver.particles();
  std::vector<glm::vec3> hair;
  float fastest = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.is_root[i]) continue;
    hair.push_back(p.position[i]);
    fastest = std::max(fastest, glm::length(p.velocity[i]));
  }
  solver.bodyDistance(hair, solver.time(), phi);
  EXPECT_GE(*std::min_element(phi.begin(), phi.end()), -kInsideTolerance) << "all out after one step";
  // Pushed out, not thrown: no particle leaves faster than a brisk hair
  // swing (the push-out's normal speed is removed).
  EXPECT_LT(fastest, 1.0f);
}

TEST(HeadScenario, AUserHeadMeshWithTheAutomaticScalpJustWorks) {
  // Another head, as a user might bring it: Y-forward, Z-up, in millimetres,
  // 10% larger, glTF-free OBJ without a torso.
  const std::string dir = ::testing::TempDir() + "loosehair-user-head";
  std::filesystem::create_directories(dir);
  TriangleMesh h = loadMesh(lhtest::sourceDir() + "/data/meshes/head.ply");
  for (auto& p : h.vertices) p = 1100.0f * glm::vec3(p.x, -p.z, p.y);
  writeObj(h, dir + "/user_head.obj");
  const std::string text = R"({"name": "user", "substeps": "auto",
    "head": {"type": "mesh", "mesh": "user_head.obj", "scale": 0.001, "up": "+z", "front": "-y"},
    "hair": {"particles": 1500, "length": 0.25, "mass": 0.05}})";
  std::ofstream(dir + "/user.json") << text;
  const SceneDesc scene = loadScene(dir + "/user.json");
  BuildReport report;
  Solver solver = buildSolver(scene, &report);
  EXPECT_GT(report.scalp_area, 0.04) << "a larger head has a larger scalp";
  EXPECT_LE(solver.initReport().unanchored, solver.particles().size() / 200) << "at most 0.5% hang on tethers only";
  const Watch w = run(solver, 1.0, scene.hair.length, [] {});
  expectInvariants(w, "user head");
  std::filesystem::remove_all(dir);
}

// A bust cut flat under the chest (the bundled torso with everything below
// y = -0.30 removed; the opening is closed by a fan) and hair long enough
// to reach under it, the head shaking: hair caught under the flat bottom,
// where the straight line to the root runs through the body, was pulled in
// by its tether and pushed back out, and stretched by 2.3%.
TEST(HeadScenario, HairUnderTheFlatBottomOfABustKeepsTheStretchBound) {
  const std::string dir = ::testing::TempDir() + "loosehair-bust";
  std::filesystem::create_directories(dir);
  TriangleMesh torso = loadMesh(lhtest::sourceDir() + "/data/meshes/torso.ply");
  std::erase_if(torso.triangles, [&](const glm::u32vec3& t) {
    return torso.vertices[t.x].y < -0.30f || torso.vertices[t.y].y < -0.30f || torso.vertices[t.z].y < -0.30f;
  });
  writeObj(torso, dir + "/bust.obj");
  const SceneDesc scene = parseScene(R"({"name": "bust", "substeps": "auto",
    "head": {"type": "mesh", "mesh": ")" +
                                         lhtest::sourceDir() + R"(/data/meshes/head.ply"},
    "torso": {"mesh": ")" + dir + R"(/bust.obj"},
    "hair": {"particles": 3000, "length": 0.45, "mass": 0.08, "whorl": [0, 0.85, -0.5],
             "w_t": 1.0, "w_n": 0.6, "bending_stiffness": 5e-4},
    "solver": {"youngs_modulus": 1e3, "hair_hair": true},
    "motion": {"type": "shake", "amplitude_deg": 40, "frequency_hz": 1.0, "cycles": 2, "start": 0.5}})",
                                     dir + "/scene.json");
  Solver solver = buildSolver(scene);
  // some hair does reach under the bust (its bottom is at y ~ -0.295)
  float lowest = 1;
  const Watch w = run(solver, 2.3, scene.hair.length, [&] {
    for (const auto& x : solver.particles().position) lowest = std::min(lowest, x.y);
  });
  EXPECT_LT(lowest, -0.31f);
  expectInvariants(w, "bust cut flat, head shaking");
  std::filesystem::remove_all(dir);
}
