// External forces in the head frame (method.md §5): gravity, air drag, the
// head's inertial forces and shape keeping.
#pragma once

#include "loosehair/head_motion.hpp"

#include <glm/vec3.hpp>

#include <cstdint>
#include <span>

namespace loosehair {

struct ShapeKeeping;  // shape_keeping.hpp

struct ExternalSettings {
  glm::vec3 gravity{0.0f};  // world (m/s^2)
  float air_drag = 0.0f;    // 1/s, on the velocity relative to still air
};

/// What the external forces read of the particles (head frame).
struct ExternalParticles {
  std::span<const glm::vec3> position, velocity;
  std::span<const float> mass;
  std::span<const std::uint8_t> is_root;
};

/// Adds m_i a_i to `force` for every particle that is not a root: gravity
/// and drag seen from the head frame, less the frame's inertial
/// acceleration (the head's motion `head` at the step's start), plus shape
/// keeping when `shape` is given. Reads `p`; adds to `force`.
void addExternalForces(const ExternalSettings& settings, const HeadKinematics& head, const ExternalParticles& p,
                       const ShapeKeeping* shape, std::span<glm::vec3> force, int threads);

}  // namespace loosehair
