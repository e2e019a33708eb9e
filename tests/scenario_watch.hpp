// Running a scenario while checking the invariants every step (or every
// few): nothing non-finite, nothing inside the head or torso, no stretch.
// Shared by the scenario tests of the bundled head and of the styles.
#pragma once

#include "test_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace lhtest {

// Penetration is measured against the exact triangles (MeshBody, tested
// against brute force in test_mesh_body.cpp); the projection puts particles
// 1 um outside, so only rounding and the crease between head and torso,
// where pushing out of one body can push into the other, remain.
inline constexpr float kInsideTolerance = 1e-5f;  // m

struct Watch {
  float worst_stretch = -1;  // max (|x - r| - s) / L_max
  float deepest = 1;         // min signed distance to the bodies (m)
  bool finite = true;
};

/// Steps to `until` seconds, checking the invariants after every
/// `check_every`-th step and the last; `each_frame` is called every 1/30 s.
template <class F>
Watch run(loosehair::Solver& solver, double until, float max_length, F each_frame, int check_every = 1) {
  Watch w;
  const int per_frame = std::max(1, static_cast<int>(std::lround(1.0 / 30.0 / solver.params().time_step)));
  std::vector<glm::vec3> hair;
  std::vector<float> phi;
  int step = 0;
  while (solver.time() < until - 1e-9) {
    solver.step();
    ++step;
    if (step % check_every == 0 || solver.time() >= until - 1e-9) {
      const auto& p = solver.particles();
      hair.clear();
      for (std::size_t i = 0; i < p.size(); ++i)
        if (!p.is_root[i]) hair.push_back(p.position[i]);
      solver.bodyDistance(hair, solver.time(), phi);
      for (float d : phi) w.deepest = std::min(w.deepest, d);
      w.worst_stretch = std::max(w.worst_stretch, maxStretch(solver, max_length));
      w.finite = w.finite && allFinite(solver);
      if (!w.finite) break;
    }
    if (step % per_frame == 0) each_frame();
  }
  return w;
}

/// A bundled scene (data/scenes/NAME.json) with its particle count changed.
inline loosehair::SceneDesc bundled(const std::string& name, int particles) {
  loosehair::SceneDesc s = loosehair::loadScene(sourceDir() + "/data/scenes/" + name + ".json");
  s.hair.particles = particles;
  return s;
}

inline void expectInvariants(const Watch& w, const std::string& what) {
  EXPECT_TRUE(w.finite) << what;
  EXPECT_GE(w.deepest, -kInsideTolerance) << what << ": a particle ended a step inside the body";
  EXPECT_LE(w.worst_stretch, 0.02f) << what << ": |x_i - r_i| <= s_i + 2% of the longest hair";
  std::printf("%s: deepest %.2e m, worst stretch %.4f\n", what.c_str(), w.deepest, w.worst_stretch);
}

}  // namespace lhtest
