// The implicit spring solve of the step (implicit_springs.hpp, method.md
// §3.3): from the spring pass's weights and directions and the step's
// forces, the velocity change that integrate applies.
#pragma once

#include "solver/implicit_springs.hpp"

#include <glm/vec3.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace loosehair {

struct SlicedConnections;  // solver/connection_passes.hpp
struct SpringScratch;      // solver/spring_scratch.hpp

struct ImplicitStepSettings {
  float damping = 0.0f;    // gamma (s)
  float tolerance = 0.0f;  // relative to the right-hand side's residual
  int max_iterations = 0;
};

/// Reads the weights, unit directions and pulls of the spring pass (`s`),
/// `force` (every force of the step), `mass` and `is_root`. Writes
/// `velocity_change`: read first as the warm start when it has one entry a
/// particle (the last step's answer, kept in snapshots), then replaced by
/// this step's. `solver` keeps the iterations' buffers.
ImplicitSpringReport solveImplicitSpringStep(const ImplicitStepSettings& settings, const SlicedConnections& sliced,
                                             const SpringScratch& s, std::span<const glm::vec3> force,
                                             std::span<const float> mass, std::span<const std::uint8_t> is_root,
                                             float dt, ImplicitSprings& solver, std::vector<glm::vec3>& velocity_change,
                                             int threads);

}  // namespace loosehair
