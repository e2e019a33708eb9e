// Shared helpers of the solver tests: small scenes and the invariants that
// many tests check (no stretch, no penetration, finite state).
#pragma once

#include "loosehair/loosehair.hpp"

#include <string>

namespace lhtest {

/// The sphere-hang scene with `particles` particles; `solver_json` and
/// `motion_json` are the whole "solver" and "motion" objects; substeps 0 = auto.
loosehair::SceneDesc sphereScene(int particles, const std::string& solver_json = "{}",
                                 const std::string& motion_json = R"({"type": "still"})",
                                 int substeps = 0);

/// max over non-root particles of (|x_i - r_i| - s_i) / L (head frame).
float maxStretch(const loosehair::Solver& solver, float hair_length);

/// Smallest signed distance of a non-root particle to the sphere head (m).
float minBodyDistance(const loosehair::Solver& solver, const loosehair::SceneDesc& scene);

bool allFinite(const loosehair::Solver& solver);

std::string sourceDir();

}  // namespace lhtest
