// The hair directions (method.md §3.3, eq. 15), in the pass that also
// measures the springs at the new positions for the next step.
#pragma once

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <span>

namespace loosehair {

struct SlicedConnections;  // solver/connection_passes.hpp

struct DirectionPassResult {
  std::size_t broken = 0;          // particles whose position, velocity or direction is not finite
  std::size_t active_entries = 0;  // connection entries with k_ij > 0 at the new positions (each pair twice)
};

/// Each non-root particle's direction becomes the normalised sum over its
/// connections of alpha_ij k_ij t_ij, t_ij the direction x_ij turned by the
/// pair's rest angle towards t_i (a particle with no active connection
/// keeps its direction).
///
/// Reads `connections` (layout, strengths c_ij, rest lengths, rest
/// angles), `weight` (alpha_ij k_ij of this step per slice entry: the
/// spring pass's), `is_root`, `position` (the step's end), `velocity` (for
/// the finiteness check only) and the directions themselves.
/// Writes `direction`, and the next step's side sums of l_ij k_ij at these
/// positions, `next_sum_root` and `next_sum_tip` (so the next step's factor
/// pass need not gather the partners again). The same bits on any
/// `threads`.
DirectionPassResult updateDirections(float h1, const SlicedConnections& connections, std::span<const float> weight,
                                     std::span<const std::uint8_t> is_root, std::span<const glm::vec3> position,
                                     std::span<const glm::vec3> velocity, std::span<glm::vec3> direction,
                                     std::span<float> next_sum_root, std::span<float> next_sum_tip, int threads);

}  // namespace loosehair
