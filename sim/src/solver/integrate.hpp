// Integration (method.md §5): symplectic Euler, with the inelastic,
// frictional body contact applied to the new velocity and speculative
// contacts.
#pragma once

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <span>

namespace loosehair {

class BodyQuery;     // solver/body_query.hpp
struct StepContext;  // solver/step_context.hpp

struct IntegrateSettings {
  float contact_thickness = 0.0f;  // m: the body contact acts within it
  float body_friction = 0.0f;      // Coulomb mu of the body contact
};

/// The particles' state integrate moves (head frame).
struct IntegrateParticles {
  std::span<glm::vec3> position, velocity;
  std::span<const float> mass, inverse_mass;  // 1/m = 0 for a root
  std::span<const std::uint8_t> is_root;
};

/// v += dv (the implicit solve's `spring_dv` when given, else dt f / m),
/// the body contact on the new velocity, x += dt v.
///
/// Reads `ctx.dt`, `ctx.force` (without `spring_dv`) and `bodies` (where they
/// are at the step's start). Writes `p.position`, `p.velocity`, and in `ctx`
/// the strain limit's first records (x, 1/m), the integrated positions and
/// the body clearances. Returns the particles in contact with a body.
/// The same bits on any `threads`.
std::size_t integrate(const IntegrateSettings& settings, const BodyQuery& bodies, const IntegrateParticles& p,
                      std::span<const glm::vec3> spring_dv, StepContext& ctx, int threads);

}  // namespace loosehair
