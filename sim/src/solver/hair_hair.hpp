// Hair-hair forces (method.md §4, eqs. 16-18): pressure, collision and
// friction between current neighbours.
#pragma once

#include "solver/neighbor_records.hpp"

#include <glm/vec3.hpp>

#include <cstddef>
#include <span>

namespace loosehair {

class NeighborGrid;

struct HairHairSettings {
  float h2 = 0.0f;         // the kernel's smoothing length (m)
  float collision = 0.0f;  // d_c of eq. 17
  float friction = 0.0f;   // d_fr of eq. 18
};

/// The particles' state the pair forces read, per particle.
struct HairHairInput {
  std::span<const glm::vec3> position, velocity, direction;
  std::span<const float> mass;
  std::span<const float> pressure_term;  // P / rho^2 (computeDensity)
};

/// Whether `records.xm` already holds (x, m) at the input's positions in the
/// search order (computeDensity of the same step made them) or is to be made.
enum class PositionRecords { Made, Make };

/// Adds every particle's pressure, collision and friction force from its
/// neighbours to `force`.
///
/// Reads `grid` (the lists at these positions), `in`, and `records.xm` when
/// `xm` is Made; writes `records` (the partners' records) and adds to
/// `force`. Each pair's force on i is hairHairPairForce (pair_forces.hpp).
/// The same bits on any `threads`.
void accumulateHairHair(const HairHairSettings& settings, const NeighborGrid& grid, const HairHairInput& in,
                        PairRecords& records, PositionRecords xm, std::span<glm::vec3> force, int threads);

}  // namespace loosehair
