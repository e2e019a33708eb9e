// The loose springs (method.md §3.2): the side factors of eqs. 10-14 that
// keep the tensile modulus as connections loosen, and the damped spring
// forces.
#pragma once

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <span>

namespace loosehair {

struct ConnectionSet;      // connection_builder.hpp
struct SlicedConnections;  // solver/connection_passes.hpp
struct SpringScratch;      // solver/spring_scratch.hpp

struct SpringSettings {
  float h1 = 0.0f;               // the springs' smoothing length (m)
  double youngs_modulus = 0.0;   // E (Pa)
  float stiffness_clamp = 0.0f;  // a side factor is at most this times its rest value
  float damping = 0.0f;          // gamma (s)
};

/// What the factor pass reads of the particles.
struct SpringParticles {
  std::span<const glm::vec3> position, velocity;
  std::span<const std::uint8_t> is_root;
  std::span<const float> cross_section;                      // A_i (eq. 9)
  std::span<const float> rest_factor_root, rest_factor_tip;  // a_r, a_t at rest (the clamp's reference)
};

/// Sizes `s` for `particles` particles and the connections; `keep_k`: keep
/// k_ij of every entry (the queries between steps read them).
void resizeSpringScratch(SpringScratch& s, std::size_t particles, const ConnectionSet& connections,
                         const SlicedConnections& sliced, bool keep_k);

/// The side factors a_r, a_t of every particle (eqs. 12-13, clamped), and
/// the spring pass's records.
///
/// Reads `connections` and `p`, and the spring sums in `s` when
/// `s.sums_current` (the direction pass of the last step measured them at
/// these positions; else they are measured here). Writes in `s` the factors,
/// the records, the clamped count and (when measured) the sums and active
/// entries; clears `s.sums_current`. The same bits on any `threads`.
void computeSpringFactors(const SpringSettings& settings, const ConnectionSet& connections, const SpringParticles& p,
                          SpringScratch& s, int threads);

/// The damped spring force of every particle (eq. 14's alpha_ij k_ij).
///
/// Reads `sliced` and the records and factors in `s` (computeSpringFactors).
/// Writes `force` (every particle's, replacing it: the first force pass of
/// a step) and in `s` each entry's alpha_ij k_ij and unit direction and each
/// particle's damping pull (the direction pass and the implicit solve read
/// them). The same bits on any `threads`.
void accumulateSpringForces(const SpringSettings& settings, const SlicedConnections& sliced, std::size_t particles,
                            SpringScratch& s, std::span<glm::vec3> force, int threads);

}  // namespace loosehair
