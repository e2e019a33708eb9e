// Hair that does not tear off (issue 43): on the bundled head, after a fast
// turn by hand, the turn back and a nod (the motion a viewer session saved,
// tests/data/drag-and-nod-motion.json) and after a 2 Hz, 40-degree nod, no
// particle or clump lies loose: every particle is joined to the rooted hair
// through particles within the springs' support 2 h1 of each other (before
// the hair chain, clumps of 18 and 37 particles lay on the shoulders), no
// particle is farther than 2 h1 from the hair of its own root region (hair
// that wandered off to another part of the head lay 12 cm from it), no
// particle is alone beyond the springs' support, and no render strand
// loops over the crown on a still head, after the turn and nod at most one
// in 500 (turns back 1.5 cm towards its root; the issue saw loops of 2-3 cm, from
// the initial strands, whose push out of the head took the normal of the
// head's distance grid where it is not one. A bang lying on the forehead
// may still curl its tip up by about 1 cm).
#include "test_support.hpp"

#include "hair_holds_measures.hpp"
#include "solver/hair_chain.hpp"
#include "loosehair/render_strands.hpp"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <numeric>

using namespace loosehair;
using lhtest::crownLoops;
using lhtest::farthestFromItsRegion;
using lhtest::fasterThan;
using lhtest::looseParticles;

namespace {

float largestNearestNeighbour(const std::vector<glm::vec3>& x) {
  float worst = 0.0f;
  for (std::size_t i = 0; i < x.size(); ++i) {
    float nearest = INFINITY;
    for (std::size_t j = 0; j < x.size(); ++j)
      if (j != i) nearest = std::min(nearest, glm::dot(x[j] - x[i], x[j] - x[i]));
    worst = std::max(worst, nearest);
  }
  return std::sqrt(worst);
}

struct After {
  std::size_t loose;
  float nearest;               // the largest nearest-neighbour distance (m)
  std::size_t fast;            // particles above 5 cm/s
  float fastest;               // m/s
  float region_gap;            // the farthest from other hair of its root region (m)
  std::size_t loops, strands;  // render strands turning back 1.5 cm over the crown, of
  float support;               // 2 h1 (m)
};

After runScene(const std::string& motion_json, double seconds, std::uint64_t seed = 1) {
  SceneDesc scene = loadScene(lhtest::sourceDir() + "/data/scenes/hang.json");
  scene.seed = seed;
  scene.motion =
      parseScene(R"({"head": {"type": "sphere", "center": [0, 0, 0], "radius": 0.1}, "motion": )" + motion_json + "}",
                 "motion")
          .motion;
  BuildReport build;
  Solver solver = buildSolver(scene, &build);
  RenderStrandOptions ro;
  ro.strands = 3000;
  const StrandField field = bindSceneStrands(scene, solver.particles(), build, ro, 2);
  // the root regions the hair chain holds hair to (hair_chain.hpp)
  const Particles& rest = solver.particles();
  const HairChain chain(solver.connections(), rest.is_root, rest.arc_length, rest.root_point, solver.params().h1);
  const double dt = solver.params().time_step;
  solver.advance(static_cast<int>(std::ceil(seconds / dt)));
  const Particles& p = solver.particles();
  std::vector<glm::vec3> pts;
  field.deform(solver, pts, 2);
  std::size_t looped = 0;
  for (float l : crownLoops(field.rest(), pts, scene.head_center.y)) looped += l > 0.015f;
  return {looseParticles(p.position, p.is_root, 2.0f * solver.params().h1),
          largestNearestNeighbour(p.position),
          fasterThan(p, 0.05f),
          lhtest::fastest(p),
          farthestFromItsRegion(p, [&](std::size_t i, std::size_t j) { return chain.inRegion(i, j); }),
          looped,
          field.strandCount(),
          2.0f * solver.params().h1};
}

void print(const char* name, const After& a) {
  std::printf(
      "%s: %zu loose, largest nearest neighbour %.1f mm, farthest from its root region's hair %.1f mm "
      "(2 h1 = %.1f), %zu of %zu strands turn back 1.5 cm over the crown, %zu above 5 cm/s, "
      "fastest %.3f m/s\n",
      name, a.loose, 1e3 * a.nearest, 1e3 * a.region_gap, 1e3 * a.support, a.loops, a.strands, a.fast, a.fastest);
}

}  // namespace

TEST(HairHolds, NoClumpComesLooseUnderAFastTurnAndANodOrAHeadBangingNod) {
  const After still = runScene(R"({"type": "still"})", 3.0);
  print("still head, 3 s", still);
  EXPECT_EQ(still.loose, 0u);
  EXPECT_LT(still.region_gap, still.support);
  EXPECT_EQ(still.loops, 0u);
  EXPECT_EQ(still.fast, 0u) << "a still head's hair at rest after 3 s (fastest " << still.fastest << " m/s)";
  // the viewer session's turn, turn back and nod end at 3.37 s; one second to settle
  const std::string drag = lhtest::sourceDir() + "/tests/data/drag-and-nod-motion.json";
  const std::string saved = readRegularFile(drag, kMaxTextFileBytes);
  const std::string motion = saved.substr(saved.find(':') + 1, saved.rfind('}') - saved.find(':') - 1);
  const After dragged = runScene(motion, 4.4);
  const After banged = runScene(R"({"type": "nod", "amplitude_deg": 40, "frequency_hz": 2, "cycles": 2})", 2.0);
  for (const auto& [name, a] : {std::pair{"turn, back and nod", dragged}, std::pair{"2 Hz 40-degree nod", banged}}) {
    print(name, a);
    EXPECT_EQ(a.loose, 0u) << name << ": particles no longer joined to the hair";
    // none alone beyond the springs' support, as on the other heads (a
    // quarter more than the still head's largest nearest-neighbour
    // distance was asked before the scenes settled: settled, the still
    // hair lies closer, 16.8 mm, and the turned hair's 22.4 mm is within
    // the support, 23.7)
    EXPECT_LT(a.nearest, a.support) << name;
    // Within the springs' support 2 h1 of hair of its own root region (the
    // issue asks for one smoothing length h1, which a still head's
    // sampling does not meet either: there the largest distance to the
    // nearest particle of any region is already 20 mm, h1 12 mm)
    EXPECT_LT(a.region_gap, a.support) << name << ": a particle away from its root region's hair";
    // On the mannequin head a small tuft at the whorl stays after the
    // violent turn and nod: 4 of 3000 strands, one second and two seconds
    // after it, the hair at rest by then (docs/design.md). Allowed: one
    // in 500.
    EXPECT_LE(a.loops, a.strands / 500) << name << ": render strands looping off the crown";
  }
}

// On a still head the hair comes to rest: 3 s after the settle, no
// particle above 5 cm/s, whatever the seed. With the implicit spring solve
// stopped at 5e-3 (the default before), 0-11 particles of each seed kept
// circling at their taut tethers at 5-18 cm/s for ever: the error the
// solve's warm start carries into the next step is a force one step late
// (docs/design.md, "The hair chain").
TEST(HairHolds, AStillHeadsHairComesToRest) {
  for (std::uint64_t seed : {2, 3, 4}) {
    const After a = runScene(R"({"type": "still"})", 3.0, seed);
    std::printf("still head, seed %llu, 3 s: %zu above 5 cm/s, fastest %.3f m/s\n",
                static_cast<unsigned long long>(seed), a.fast, a.fastest);
    EXPECT_EQ(a.fast, 0u) << "seed " << seed << ": fastest " << a.fastest << " m/s";
  }
}

// The issue's other case: with a higher Young's modulus and the wind on,
// clumps blew away. The bundled wind scene at 4 times its modulus: without
// the chain 5-10 particles are loose at 1-3 s and one lies 10 cm from the
// hair of its root region; with it none, and all within 2 h1.
TEST(HairHolds, NoClumpBlowsAwayInTheWindWithStifferHair) {
  SceneDesc scene = loadScene(lhtest::sourceDir() + "/data/scenes/wind.json");
  scene.sim.youngs_modulus *= 4.0f;
  Solver solver = buildSolver(scene);
  const Particles& rest = solver.particles();
  const HairChain chain(solver.connections(), rest.is_root, rest.arc_length, rest.root_point, solver.params().h1);
  const float support = 2.0f * solver.params().h1;
  for (double t : {1.0, 2.0, 3.0}) {
    solver.advance(static_cast<int>(std::lround((t - solver.time()) / solver.params().time_step)));
    const Particles& p = solver.particles();
    const std::size_t loose = looseParticles(p.position, p.is_root, support);
    const float gap = farthestFromItsRegion(p, [&](std::size_t i, std::size_t j) { return chain.inRegion(i, j); });
    std::printf("wind, 4x the modulus, %.0f s: %zu loose, farthest from its root region's hair %.1f mm (2 h1 = %.1f)\n",
                t, loose, 1e3 * gap, 1e3 * support);
    EXPECT_EQ(loose, 0u) << t << " s";
    EXPECT_LT(gap, support) << t << " s";
  }
}
