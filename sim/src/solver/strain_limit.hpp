// The strain limit (method.md §5): after the step, each over-stretched
// active connection is moved back towards (1 + max_strain) l_ij, the two
// particles weighted by inverse mass, roots immovable, in Jacobi rounds.
#pragma once

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace loosehair {

struct SlicedConnections;  // solver/connection_passes.hpp

struct StrainLimitSettings {
  float h1 = 0.0f;          // the springs' smoothing length (m): W(r, h1) and the support 2 h1
  float max_strain = 0.0f;  // a connection may be (1 + max_strain) l_ij long
  int rounds = 0;           // Jacobi rounds at most (it stops when none acts)
};

/// Moves over-stretched connections back within (1 + max_strain) l_ij.
///
/// Reads `connections` (the slice layout and the rest lengths l_ij),
/// `is_root` and `records[0]`: (x, 1/m) of every particle at `position`
/// (integrate makes them in its pass; 1/m = 0 for a root).
/// Writes `position`, and uses `records[1]` and `scratch` (any size; they
/// are resized) as the other buffers of the rounds.
/// Returns how many particles the first round moved. The same bits on any
/// `threads`.
std::size_t limitStrain(const StrainLimitSettings& settings, const SlicedConnections& connections,
                        std::span<const std::uint8_t> is_root, std::vector<glm::vec3>& position,
                        std::vector<glm::vec4> (&records)[2], std::vector<glm::vec3>& scratch, int threads);

}  // namespace loosehair
