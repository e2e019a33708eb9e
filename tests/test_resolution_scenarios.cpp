// The same physics at any resolution (issue 18, "real time at scale"): the
// bundled hang, head-shake and back-hair-split scenes at 6,000 and 50,000
// particles with the default solver (implicit springs, 3 substeps a frame)
// keep the stretch bound and the bodies' surfaces; the hanging hair's tip
// sag and the shaken hair's lag agree between the two resolutions (the
// stiffness does not depend on the spacing, method.md §3.2); the head-shake gain
// and lag agree with the explicit solver's; with hair-hair interactions the
// split wisps interpenetrate less than without, at 50,000 particles too.
#include "back_hair_split.hpp"
#include "scenario_watch.hpp"
#include "test_support.hpp"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

using namespace loosehair;

using lhtest::bundled;

namespace {

// The invariants once a frame at 50k (the exact distances of every
// particle each step would cost more than the simulation).
int checkEvery(int particles) { return particles > 20000 ? 3 : 1; }

// Mean drop below their roots of the hanging hair's tips (the particles in
// the longest fifth of arc length), after 3 s (m).
double tipSag(int particles) {
  const SceneDesc scene = bundled("hang", particles);
  Solver solver = buildSolver(scene);
  const lhtest::Watch w = lhtest::run(
      solver, 3.0, scene.hair.length, [] {}, checkEvery(particles));
  lhtest::expectInvariants(w, "hang, " + std::to_string(particles) + " particles");
  const auto& p = solver.particles();
  float longest = 0;
  for (float s : p.arc_length) longest = std::max(longest, s);
  double drop = 0;
  int n = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (!p.is_root[i] && p.arc_length[i] > 0.8f * longest) {
      drop += p.root_point[i].y - p.position[i].y;
      ++n;
    }
  return drop / n;
}

lhtest::GainLag shake(int particles, bool implicit) {
  SceneDesc scene = bundled("head-shake", particles);
  scene.sim.implicit_springs = implicit;
  Solver solver = buildSolver(scene);
  std::vector<glm::vec3> start;
  solver.worldPositions(start);
  std::vector<double> t, head, hair;
  const lhtest::Watch w = lhtest::run(
      solver, 3.5, scene.hair.length,
      [&] {
        t.push_back(solver.time());
        head.push_back(lhtest::headYaw(solver));
        hair.push_back(lhtest::hairYaw(solver, start, 0.12f));
      },
      checkEvery(particles));
  lhtest::expectInvariants(w, std::string("head-shake, ") + std::to_string(particles) + " particles, " +
                                  (implicit ? "implicit" : "explicit") + " springs");
  const lhtest::GainLag gl = lhtest::fitGainAndLag(t, head, hair, 0.6, 2.5);
  std::printf("head-shake, %d particles, %s springs: gain %.3f, lag %.1f ms\n", particles,
              implicit ? "implicit" : "explicit", gl.gain, gl.lag * 1e3);
  return gl;
}

}  // namespace

TEST(Resolution, HangingHairSagsAlikeAt6kAnd50kParticles) {
  const double coarse = tipSag(6000), fine = tipSag(50000);
  std::printf("tip sag below the roots: %.4f m at 6k, %.4f m at 50k particles (%.1f%%)\n", coarse, fine,
              100.0 * (fine / coarse - 1.0));
  ASSERT_GT(coarse, 0.1) << "the long hair hangs below its roots";
  EXPECT_LT(std::abs(fine / coarse - 1.0), 0.05);
}

TEST(Resolution, ShakenHairLagsAlikeAt6kAnd50kAndAsTheExplicitSolver) {
  const lhtest::GainLag coarse = shake(6000, true), fine = shake(50000, true);
  const lhtest::GainLag explicit_coarse = shake(6000, false);
  EXPECT_LT(std::abs(fine.lag / coarse.lag - 1.0), 0.05) << "lag at 50k against 6k";
  EXPECT_LT(std::abs(coarse.gain / explicit_coarse.gain - 1.0), 0.2) << "gain, implicit against explicit";
  EXPECT_LT(std::abs(coarse.lag / explicit_coarse.lag - 1.0), 0.2) << "lag, implicit against explicit";
}

TEST(Resolution, SplitWispsAt50kInterpenetrateLessWithHairHairInteractions) {
  const lhtest::SplitRun with = lhtest::runSplit(true, 1, 50000, 3), without = lhtest::runSplit(false, 1, 50000, 3);
  const double before = lhtest::meanOver(with, with.middle, 0.1, 0.3);
  const double split = lhtest::meanOver(with, with.middle, 1.3, 1.5);
  const double a = lhtest::meanOver(with, with.cross, 1.5, 3.0), b = lhtest::meanOver(without, without.cross, 1.5, 3.0);
  std::printf(
      "50k: particles in the parting before %.0f, split %.0f; interpenetration while merging %.4f with "
      "hair-hair interactions, %.4f without\n",
      before, split, a, b);
  EXPECT_LT(split, 0.3 * before) << "the back hair splits into two wisps";
  EXPECT_LT(a, b);
}
