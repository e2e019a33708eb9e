// What one step hands from stage to stage (Solver::step; the order and the
// data flow are drawn in docs/design.md, "One step"). The inputs are set
// before the first stage. Every other field is written by the stages its
// comment names and read only by the stages after them; the buffers stay
// allocated from step to step.
// Nothing here outlives the step: what a step leaves for the next (the
// spring sums of the direction pass, the implicit solve's warm start) is
// the solver's state.
#pragma once

#include "loosehair/solver.hpp"
#include "solver/neighbor_records.hpp"

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace loosehair {

struct StepContext {
  // ---- inputs ------------------------------------------------------------
  float dt = 0.0f;  // the step (s)
  /// The step after Solver::setKinematicState: the corrections put the
  /// particles where they belong without making their moves velocities.
  bool absorb_corrections = false;

  // ---- density -> hair-hair ----------------------------------------------
  /// The partners' records in the search order: the density pass writes
  /// the (x, m) records, the hair-hair pass reads them and writes the rest.
  /// (The density itself and P / rho^2 are the solver's: the queries read
  /// them between steps.)
  PairRecords pair_records;

  // ---- the forces -> the implicit solve, integrate ------------------------
  /// Every force on each particle this step (N, head frame): written by the
  /// spring pass, added to by hair-hair, the wind's air and the external
  /// forces; read by the implicit spring solve and by integrate.
  std::vector<glm::vec3> force;

  // ---- integrate -> strain limit -----------------------------------------
  /// (x, 1/m) of every particle where integrate left it (1/m = 0 for a
  /// root): the strain limit's first round reads [0], each round writes the
  /// other for the next.
  std::vector<glm::vec4> strain_records[2];
  std::vector<glm::vec3> limited_position;  // the strain limit's output buffer

  // ---- integrate -> body contacts ----------------------------------------
  /// Positions as integrate left them, before any correction.
  std::vector<glm::vec3> integrated_position;
  /// A lower bound of each particle's distance from every body at its
  /// integrated position, the bodies where they were at the step's start
  /// (-inf: not known); the body contacts skip whom it proves clear.
  std::vector<float> body_clearance;

  // ---- hair chain -> body contacts ---------------------------------------
  /// The particles the hair chain moved (empty: the chain is off); their
  /// moves only stop a motion against them (body_contacts.cpp).
  std::vector<std::uint8_t> chain_moved;

  // ---- outputs -------------------------------------------------------------
  StageTimes times;
  std::size_t contacts = 0;  // particles in contact with a body in integrate
  std::size_t limited = 0;   // particles the strain limit moved in its first round

  /// Sizes the per-particle buffers for n particles.
  void resize(std::size_t n) {
    force.assign(n, glm::vec3(0.0f));
    integrated_position.resize(n);
    body_clearance.resize(n, -INFINITY);
    limited_position.resize(n);
  }
};

}  // namespace loosehair
