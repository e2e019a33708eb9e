// SPH density (method.md §2 eq. 1) and the pressure terms of eq. 16.
#pragma once

#include "solver/neighbor_records.hpp"

#include <glm/vec3.hpp>

#include <cstddef>
#include <span>

namespace loosehair {

class NeighborGrid;

struct DensitySettings {
  float h2 = 0.0f;                  // the density kernel's smoothing length (m)
  float pressure_stiffness = 0.0f;  // k_a of P = k_a (rho - rho0)
  float rest_density = 0.0f;        // rho0 (kg/m^3)
};

/// The density of every particle, its pressure and P / rho^2 (eq. 16's term).
///
/// Reads `grid` (its lists, built at `position` in the search order),
/// `position` and `mass`. Writes `density`, `pressure` and `pressure_term`
/// (per particle), and `records.xm`: the (x, m) records in the search order,
/// which the hair-hair pass of the same step reuses (accumulateHairHair).
/// The same bits on any `threads`.
void computeDensity(const DensitySettings& settings, const NeighborGrid& grid, std::span<const glm::vec3> position,
                    std::span<const float> mass, PairRecords& records, std::span<float> density,
                    std::span<float> pressure, std::span<float> pressure_term, int threads);

}  // namespace loosehair
