// Growing a scene's hair particles (method.md §6): from a style's strands
// or hung by cantilever strands from the scalp; scene_build.cpp makes the
// solver from them.
#pragma once

#include "loosehair/head_model.hpp"
#include "loosehair/particles.hpp"
#include "loosehair/scene.hpp"

#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace loosehair {

// The hair between the scalp and a tie, per particle: its tether towards
// the tie (Solver::setTieTethers) and the tie's hold (HairTie::hold, given
// to Solver::setShapeKeepingStrengths).
struct TieTethers {
  std::vector<glm::vec3> point;
  std::vector<float> reach;  // < 0: none
  std::vector<float> hold;   // Hz; 0 where reach < 0
  /// The entries of the particles `which` (as Particles::select).
  void select(const std::vector<std::uint32_t>& which) {
    if (reach.empty()) return;
    TieTethers t;
    for (std::uint32_t k : which) {
      t.point.push_back(point[k]);
      t.reach.push_back(reach[k]);
      t.hold.push_back(hold[k]);
    }
    *this = std::move(t);
  }
};

// The threads the scene's build runs on: solver.threads where it is in
// range (one out of range is refused with the other solver parameters
// once the particles are made: until then, the default), else all.
int buildThreads(const SceneDesc& scene);

/// The particles of a styled scene into `p`, the Poisson radius into `rp`,
/// the tethers of hair between the scalp and a tie into `tethers`. Returns
/// the style's own shape-keeping strength (Hz).
float growFromStyle(const SceneDesc& scene, const HeadModel& model, Particles& p, float& rp, BuildReport& rep,
                    TieTethers& tethers);

/// The particles of a scene without a style into `p`, the Poisson radius
/// into `rp`.
void growCantilever(const SceneDesc& scene, const HeadModel& model, Particles& p, float& rp, BuildReport& rep);

}  // namespace loosehair
