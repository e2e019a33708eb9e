// The back-hair-split scenario's measures (method.md §8): the obstacle parts the
// back hair into two wisps, which fall back together. Shared by the head
// scenario tests and the resolution tests.
#pragma once

#include "scenario_watch.hpp"
#include "test_support.hpp"

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace lhtest {

struct SplitRun {
  std::vector<double> t, cross, middle;
  Watch watch;
};

// Back hair: particles rooted behind the ears; the wisps are the left and
// right halves (root x < 0, > 0). `cross`: the fraction of back hair that is
// on the other wisp's side of the parting plane x = 0 by more than 5 mm
// (the wisps interpenetrate). `middle`: back-hair particles within 1 cm of
// the plane at the height of the obstacle (the gap of the split). The
// invariants are checked every `check_every` steps. `hair_chain`: the
// solver's switch (on by default).
inline SplitRun runSplit(bool hair_hair, std::uint64_t seed, int particles = 3000, int check_every = 1,
                         bool hair_chain = true) {
  loosehair::SceneDesc scene = bundled("back-hair-split", particles);
  scene.sim.hair_hair = hair_hair;
  scene.sim.hair_chain = hair_chain;
  scene.seed = seed;
  loosehair::Solver solver = loosehair::buildSolver(scene);
  SplitRun r;
  r.watch = run(
      solver, 3.0, scene.hair.length,
      [&] {
        const auto& p = solver.particles();
        double back = 0, cross = 0, middle = 0;
        for (std::size_t i = 0; i < p.size(); ++i) {
          if (p.is_root[i] || p.root_point[i].z > -0.03f || p.arc_length[i] < 0.02f) continue;
          back += 1;
          const float x = p.position[i].x, side = p.root_point[i].x;
          if ((side < 0 && x > 0.005f) || (side > 0 && x < -0.005f)) cross += 1;
          if (std::abs(x) < 0.01f && p.position[i].y < -0.12f && p.position[i].y > -0.26f) middle += 1;
        }
        r.t.push_back(solver.time());
        r.cross.push_back(cross / back);
        r.middle.push_back(middle);
      },
      check_every);
  expectInvariants(r.watch, std::string(hair_hair ? "back-hair-split" : "back-hair-split without hair-hair") + ", " +
                                std::to_string(particles) + " particles");
  return r;
}

inline double meanOver(const SplitRun& r, const std::vector<double>& v, double from, double to) {
  double sum = 0;
  int n = 0;
  for (std::size_t k = 0; k < r.t.size(); ++k)
    if (r.t[k] >= from && r.t[k] <= to) {
      sum += v[k];
      ++n;
    }
  return sum / n;
}

}  // namespace lhtest
