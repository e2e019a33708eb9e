// Building the fixed connection set (method.md §3.1).
#pragma once

#include "loosehair/connections.hpp"

#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>

namespace loosehair {

/// Alignment a_ij of method.md §3.1 (eq. 6 reconstructed) for directions t_i, t_j
/// and the pair vector x_ij = x_j - x_i (any length > 0).
float alignment(const glm::vec3& ti, const glm::vec3& tj, const glm::vec3& xij);

/// sin(theta_ij) from cos(theta_ij) (ConnectionSet::sin_rest). The solver's
/// direction pass computes it with this same function rather than streaming
/// the stored column, so both give the same bits.
inline float restSine(float cos_theta) { return std::sqrt(std::max(0.0f, 1.0f - cos_theta * cos_theta)); }

struct ConnectionOptions {
  float h1 = 0.0f;                   // m
  float alignment_threshold = 0.5f;  // a0
  int target_connections = 12;       // Nn
  int threads = 1;
};

/// Connections between every pair closer than 2*h1 whose alignment is at
/// least a0, pruned to about Nn per particle. Root-root pairs are left out:
/// both ends are fixed, so such a spring could never act.
///
/// Pruning (method.md §3.1 open, our rule): pairs are visited from the weakest
/// weight c_ij W(l_ij, h1) up (ties by the lower, then the higher index) and
/// dropped while both partners still have more than Nn. A non-root particle's
/// strongest root-side and strongest tip-side pair are never dropped, so
/// pruning cannot cut a particle off from the root or the tip where a
/// neighbour existed. A non-root particle with no aligned pair towards the
/// root keeps its strongest pair with 0 < a_ij < a0 on that side, so that it
/// does not hang on nothing. Deterministic: it does not depend on `threads`.
ConnectionSet buildConnections(std::span<const glm::vec3> x, std::span<const glm::vec3> t, std::span<const float> s,
                               std::span<const std::uint8_t> is_root, const ConnectionOptions& options);

/// Non-root particles that cannot reach a root particle by following
/// root-side connections (method.md §3.1 connectivity check).
std::size_t countUnanchored(const ConnectionSet& c, std::span<const std::uint8_t> is_root);

}  // namespace loosehair
