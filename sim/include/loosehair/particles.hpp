// Struct-of-arrays particle storage (method.md §1).
// Positions, velocities and directions are in the head frame: roots are fixed
// there and inertial forces stand for the head's motion (method.md §5).
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace loosehair {

struct Particles {
  // hot: read or written every step
  std::vector<glm::vec3> position;    // x_i, head frame (m)
  std::vector<glm::vec3> velocity;    // v_i, relative to the head frame (m/s)
  std::vector<glm::vec3> direction;   // t_i, unit hair direction, head frame
  std::vector<float> mass;            // m_i (kg)
  std::vector<std::uint8_t> is_root;  // 1: attached to the head, never integrated: s_i < 0, or held by a hair tie

  // cold: constant after initialisation
  std::vector<glm::vec2> uv;          // (u_i, v_i) in the scalp domain [0,1]^2
  std::vector<float> arc_length;      // s_i (m); negative for roots
  std::vector<glm::vec3> root_point;  // f^-1(u_i, v_i), the strand's scalp point, head frame

  std::size_t size() const { return position.size(); }
  void resize(std::size_t n);
  /// The particles `which[0]`, `which[1]`, ... in that order (indices in range).
  Particles select(const std::vector<std::uint32_t>& which) const;
  /// Throws std::invalid_argument if the arrays disagree in length or hold
  /// non-finite values, zero masses or non-unit directions.
  void check() const;
};

}  // namespace loosehair
