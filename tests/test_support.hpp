// Shared helpers of the solver tests: small scenes and the invariants that
// many tests check (no stretch, no penetration, finite state).
#pragma once

#include "loosehair/loosehair.hpp"
#include "loosehair/strand_field.hpp"

#include <glm/vec3.hpp>

#include <string>
#include <vector>

namespace lhtest {

/// The sphere-hang scene with `particles` particles; `solver_json` and
/// `motion_json` are the whole "solver" and "motion" objects; substeps 0 = auto.
loosehair::SceneDesc sphereScene(int particles, const std::string& solver_json = "{}",
                                 const std::string& motion_json = R"({"type": "still"})", int substeps = 0);

/// max over non-root particles of (|x_i - r_i| - s_i) / L (head frame).
float maxStretch(const loosehair::Solver& solver, float hair_length);

/// Smallest signed distance of a non-root particle to the sphere head (m).
float minBodyDistance(const loosehair::Solver& solver, const loosehair::SceneDesc& scene);

bool allFinite(const loosehair::Solver& solver);

/// The head's world yaw about +Y (rad).
double headYaw(const loosehair::Solver& solver);
/// Mean world yaw about the vertical axis of the particles with arc length
/// >= min_arc_length (the part near the scalp turns with it), relative to
/// `start` (world positions), weighted by the distance from the axis (rad).
/// Only the particles i with only[i] != 0 when `only` is not empty.
double hairYaw(const loosehair::Solver& solver, const std::vector<glm::vec3>& start, float min_arc_length,
               const std::vector<std::uint8_t>& only = {});
/// Least-squares fit hair(t) ~ gain head(t) - lag head'(t) over samples with
/// from <= t <= to: a follower delayed by lag is head(t - lag) ~ head - lag head'.
struct GainLag {
  double gain, lag;
};
GainLag fitGainAndLag(const std::vector<double>& t, const std::vector<double>& head, const std::vector<double>& hair,
                      double from, double to);

std::string sourceDir();

/// Largest |strand length / rest length - 1| over the strands of `field`
/// at `points` (StrandField::deform's output).
float strandLengthError(const loosehair::StrandField& field, const std::vector<glm::vec3>& points);
/// Appends, for every inner strand point, how much more the strand turns
/// there (degrees, between its two segments) than at rest.
void extraTurns(const loosehair::StrandField& field, const std::vector<glm::vec3>& points, std::vector<float>& out);

/// Appends a closed box [lo, hi] to `mesh` as a part of its own (12
/// triangles, counter-clockwise seen from outside).
void addBox(loosehair::TriangleMesh& mesh, glm::vec3 lo, glm::vec3 hi);

}  // namespace lhtest
