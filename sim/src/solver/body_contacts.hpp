// Body contacts after the corrections (method.md §5 body collisions): no
// particle left inside a body; the corrections' moves become velocities.
#pragma once

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace loosehair {

struct StepContext;  // solver/step_context.hpp

/// The bodies where they are at the step's end, as the body contacts ask
/// them (Solver answers with its placed bodies, body_contacts.cpp).
class ContactBodies {
 public:
  virtual ~ContactBodies() = default;
  /// The exact nearest surface (phi < 0 inside), its outward normal and
  /// velocity at x[0..n), the points being the particles `index`; with the
  /// obstacles or without them (`with_obstacles`).
  virtual void nearest(const glm::vec3* x, std::size_t n, const std::uint32_t* index, bool with_obstacles, float* phi,
                       glm::vec3* normal, glm::vec3* surface_velocity) const = 0;
  /// A lower bound of each particle [first, first + count)'s distance from
  /// every body where it is now (-inf: none known), into `lower`; one call
  /// a block of particles.
  virtual void clearance(std::size_t first, std::size_t count, float* lower) const = 0;
  /// Rounds with the obstacles (more where bodies may meet in a crease).
  virtual int rounds() const = 0;
  virtual bool hasObstacles() const = 0;
};

struct BodyContactSettings {
  bool slide = false;           // tethers on: a push through a tether slides round the body
  float tether_slack = 0.0f;    // a tether's reach is (1 + slack) s
  float trapped_excess = 0.0f;  // m beyond its reach: a pushed particle is caught (freeTrappedHair)
};

/// The particles' state the body contacts move.
struct BodyContactParticles {
  std::span<glm::vec3> position, velocity;
  std::span<const std::uint8_t> is_root;
  std::span<const glm::vec3> root_point;
  std::span<const float> arc_length;
};

/// Projects what is inside a body to its surface (a few rounds: bodies may
/// meet in a crease, where leaving one can mean entering another) and takes
/// the new velocity from the corrected positions (no added normal speed,
/// so nothing is thrown off the body).
///
/// Reads from `ctx` the step, the integrated positions, integrate's
/// clearances (through `bodies.clearance`), the chain's moves and whether
/// to absorb the corrections. Writes positions and velocities, and
/// `trapped` (sized to the particles when `settings.slide`: pushed out
/// beyond the tether's reach). Returns whether any particle was trapped.
/// The same bits on any `threads`.
bool projectOutOfBodies(const BodyContactSettings& settings, const ContactBodies& bodies, const BodyContactParticles& p,
                        const StepContext& ctx, std::vector<std::uint8_t>& trapped, int threads);

}  // namespace loosehair
