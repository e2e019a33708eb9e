// Tethers (our addition to method.md §5; tether.hpp): no particle farther
// from its root point than (1 + slack) times its arc length, nor from its
// tie (a hair tie's ring) than its reach there.
#pragma once

#include <glm/vec3.hpp>

#include <cstdint>
#include <span>

namespace loosehair {

/// Moves each non-root particle along the line to its root point until it
/// is within (1 + slack) s_i of it, then likewise towards its tie point
/// where it has one (reach >= 0).
///
/// Reads `is_root`, `root_point`, `arc_length` (s_i), and `tie_point`,
/// `tie_reach` (both empty: no ties). Writes `position`. Each particle
/// alone: the same bits on any `threads`.
void applyTethers(float slack, std::span<const std::uint8_t> is_root, std::span<const glm::vec3> root_point,
                  std::span<const float> arc_length, std::span<const glm::vec3> tie_point,
                  std::span<const float> tie_reach, std::span<glm::vec3> position, int threads);

}  // namespace loosehair
